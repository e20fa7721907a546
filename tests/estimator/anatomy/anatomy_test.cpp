#include <gtest/gtest.h>

#include <cmath>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"

namespace spinewatch {
namespace {

TEST(SpineSpec, GenericFileParsesWithPublishedChainLengths) {
  const SpineSpec& spec = generic_spine_spec();
  double thoracic = 0, lumbar = 0;
  for (std::size_t i = 0; i < 11; ++i) thoracic += spec.vertebrae[i].spacing_mm;
  for (std::size_t i = 11; i < 16; ++i) lumbar += spec.vertebrae[i].spacing_mm;
  EXPECT_NEAR(thoracic, 300, 5);  // spine-facts: thoracic chain ≈ 300 mm
  EXPECT_NEAR(lumbar, 170, 5);    // lumbar chain (with T12–L1) ≈ 170 mm
  EXPECT_EQ(spec.joints[15].name, "L4-L5");
}

TEST(SpineSpec, BadFilesNameTheProblem) {
  std::string text(generic_spine_toml());
  auto broken = text;
  broken.replace(broken.find("name = \"T7\""), 11, "name = \"T8\"");
  auto r = parse_spine_spec(broken, "s.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("vertebra[6].name: expected \"T7\""), std::string::npos) << r.error().message;

  auto negative = text;
  negative.replace(negative.find("height_mm = 14.0"), 16, "height_mm = -1.0");
  r = parse_spine_spec(negative, "s.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("vertebra[0].height_mm: -1 is out of range"), std::string::npos) << r.error().message;
  EXPECT_EQ(r.error().message.rfind("s.toml:", 0), 0u);
}

TEST(NeutralPose, SagittalCurvesWithT1AboveL5) {
  const SpinePose pose = neutral_pose(generic_spine_spec(), 1750);
  EXPECT_NEAR(pose[kWaistIndex].body_center.y(), 0.575 * 1750, 1e-9);
  const Eigen::Vector3d chord = pose[kNeckIndex].body_center - pose[kWaistIndex].body_center;
  EXPECT_GT(chord.y(), 420);
  EXPECT_LT(chord.y(), 470);
  EXPECT_LT(std::abs(chord.x()), 40);
  for (const auto& v : pose) {
    EXPECT_DOUBLE_EQ(v.body_center.z(), 0);
    EXPECT_TRUE(v.q.isApprox(Eigen::Quaterniond::Identity()));
  }
  // Kyphosis: mid-thoracic vertebrae lie posterior of the T1–T12 chord.
  const double x_chord = 0.5 * (pose[0].body_center.x() + pose[11].body_center.x());
  EXPECT_LT(pose[6].body_center.x(), x_chord - 10);
  // Lordosis: L3 lies anterior of the T12–L5 chord.
  const double x_lchord = 0.5 * (pose[11].body_center.x() + pose[16].body_center.x());
  EXPECT_GT(pose[14].body_center.x(), x_lchord + 5);
}

TEST(Kinematics, JointAnglesInvertJointRotation) {
  for (double f : {-20.0, 0.0, 7.5, 35.0})
    for (double l : {-15.0, 0.0, 9.0})
      for (double t : {-12.0, 0.0, 4.0}) {
        const JointAngles a = joint_angles(joint_rotation({f, l, t}));
        EXPECT_NEAR(a.flexion, f, 1e-9);
        EXPECT_NEAR(a.lateral, l, 1e-9);
        EXPECT_NEAR(a.twist, t, 1e-9);
      }
}

TEST(Kinematics, ZeroMotionIsNeutral) {
  const SpinePose neutral = neutral_pose(generic_spine_spec(), 1750);
  const SpinePose pose = pose_spine(neutral, SegmentalMotion{});
  for (std::size_t i = 0; i < kVertebraCount; ++i)
    EXPECT_LT((pose[i].body_center - neutral[i].body_center).norm(), 1e-9);
}

TEST(Kinematics, BendsGoTheDocumentedWayAndKeepSpacing) {
  const SpineSpec& spec = generic_spine_spec();
  const SpinePose neutral = neutral_pose(spec, 1750);
  const SpinePose flexed = pose_spine(neutral, distribute(spec, 40, 0, 0));
  EXPECT_GT(flexed[0].body_center.x() - neutral[0].body_center.x(), 100);   // T1 forward
  const SpinePose right = pose_spine(neutral, distribute(spec, 0, 20, 0));
  EXPECT_GT(right[0].body_center.z(), 50);                                  // T1 to the right
  const SpinePose twisted = pose_spine(neutral, distribute(spec, 0, 0, 20));
  const Eigen::Vector3d anterior = twisted[0].q * Eigen::Vector3d::UnitX();
  EXPECT_LT(anterior.z(), -0.2);                                            // faces left
  // Joints pivot about the disc centre, so body-centre spacing changes only
  // to second order in the joint angle (a few hundredths of a mm here).
  for (const SpinePose* p : {&flexed, &right, &twisted})
    for (std::size_t i = 0; i + 1 < kVertebraCount; ++i)
      EXPECT_NEAR(((*p)[i].body_center - (*p)[i + 1].body_center).norm(),
                  (neutral[i].body_center - neutral[i + 1].body_center).norm(), 0.05);
  // The distributed angles come back out of the posed spine.
  const auto angles = intervertebral_angles(flexed);
  const SegmentalMotion m = distribute(spec, 40, 0, 0);
  double total = 0;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    EXPECT_NEAR(angles[i].flexion, m.joints[i].flexion, 1e-6);
    total += angles[i].flexion;
  }
  EXPECT_NEAR(total, 40, 1e-6);
}

}  // namespace
}  // namespace spinewatch
