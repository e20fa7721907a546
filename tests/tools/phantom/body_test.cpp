#include <gtest/gtest.h>

#include <cmath>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/units.hpp"
#include "spinewatch/phantom/body.hpp"

namespace spinewatch::phantom {
namespace {

double angle_from_vertical_deg(const Eigen::Vector3d& dir) {
  return std::acos(std::clamp(dir.normalized().y(), -1.0, 1.0)) * kDegPerRad;
}

TEST(PhantomBody, StandsAndSitsWithL5AboveTheOrigin) {
  Subject subject;
  subject.height_mm = 1600;
  const BodyModel standing(subject, SubjectPosture::Standing, 1);
  const Eigen::Vector3d l5 = standing.neutral()[kWaistIndex].body_center;
  EXPECT_DOUBLE_EQ(l5.x(), 0);
  EXPECT_DOUBLE_EQ(l5.z(), 0);
  EXPECT_NEAR(l5.y(), generic_spine_spec().l5_height_fraction * 1600, 1e-9);

  const BodyModel seated(subject, SubjectPosture::Seated, 1);
  const Eigen::Vector3d seated_l5 = seated.neutral()[kWaistIndex].body_center;
  EXPECT_DOUBLE_EQ(seated_l5.x(), 0);
  EXPECT_GT(seated_l5.y(), subject.seat_height_mm + 100);
  EXPECT_LT(seated_l5.y(), subject.seat_height_mm + 250);
}

TEST(PhantomBody, GroundTruthIsTheEstimatorKinematics) {
  const BodyModel body(Subject{}, SubjectPosture::Standing, 5);
  const TrunkMotion motion{.flexion_deg = 30, .lateral_deg = 10, .twist_deg = -8};
  const BodyPose pose = body.pose(motion);
  const SpinePose expected = pose_spine(body.neutral(), body.segmental_motion(motion));
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    EXPECT_TRUE(pose.spine[i].body_center.isApprox(expected[i].body_center, 1e-12)) << kVertebraNames[i];
    EXPECT_TRUE(pose.spine[i].q.isApprox(expected[i].q, 1e-12)) << kVertebraNames[i];
  }
  EXPECT_FALSE(pose.solids.empty());
}

TEST(PhantomBody, FlexionIsTwoThirdsSpineOneThirdPelvis) {
  const BodyModel body(Subject{}, SubjectPosture::Standing, 9);
  const SegmentalMotion m = body.segmental_motion({.flexion_deg = 45, .lateral_deg = 20, .twist_deg = 12});
  double flexion = 0, lateral = 0, twist = 0;
  for (const auto& j : m.joints) {
    flexion += j.flexion;
    lateral += j.lateral;
    twist += j.twist;
  }
  EXPECT_NEAR(flexion, 30, 1e-9);
  EXPECT_NEAR(m.pelvis.flexion, 15, 1e-9);
  EXPECT_NEAR(lateral, 20, 1e-9);
  EXPECT_NEAR(twist, 12, 1e-9);

  // Pure flexion: T1's axis tips forward by the whole trunk angle, and the
  // pelvis tilting about the hips carries L5 forward.
  const BodyPose pose = body.pose({.flexion_deg = 45});
  const Eigen::Vector3d neck_dir = pose.spine[kNeckIndex].q * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(angle_from_vertical_deg(neck_dir), 45, 1e-6);
  EXPECT_GT(neck_dir.x(), 0);
  EXPECT_NEAR(angle_from_vertical_deg(pose.spine[kWaistIndex].q * Eigen::Vector3d::UnitY()), 15, 1e-6);
  EXPECT_GT(pose.spine[kWaistIndex].body_center.x(), 5);
}

TEST(PhantomBody, JointSharesVaryPerSubjectWithinTwentyPercent) {
  const BodyModel a(Subject{}, SubjectPosture::Standing, 1);
  const BodyModel a_again(Subject{}, SubjectPosture::Standing, 1);
  const BodyModel b(Subject{}, SubjectPosture::Standing, 2);
  bool differs = false;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    for (double f : {a.joint_factors()[i].flexion, a.joint_factors()[i].lateral, a.joint_factors()[i].twist}) {
      EXPECT_GE(f, 0.8);
      EXPECT_LE(f, 1.2);
    }
    EXPECT_EQ(a.joint_factors()[i].flexion, a_again.joint_factors()[i].flexion);
    differs = differs || a.joint_factors()[i].flexion != b.joint_factors()[i].flexion;
  }
  EXPECT_TRUE(differs);

  // Not bending exactly like the generic model.
  const SegmentalMotion generic = distribute(generic_spine_spec(), 30, 0, 0);
  const SegmentalMotion subject = a.segmental_motion({.flexion_deg = 45});
  double largest = 0;
  for (std::size_t i = 0; i < kJointCount; ++i)
    largest = std::max(largest, std::abs(subject.joints[i].flexion / generic.joints[i].flexion - 1));
  EXPECT_GT(largest, 0.02);
  EXPECT_LT(largest, 0.51);
}

TEST(PhantomBody, FactorsFromTheSubjectFileWin) {
  Subject subject;
  subject.joint_factors.emplace();
  for (auto& f : *subject.joint_factors) f = {1, 1, 1};
  (*subject.joint_factors)[15].flexion = 2.0;  // L4-L5 bends twice its generic share
  const BodyModel body(subject, SubjectPosture::Standing, 123);
  const SegmentalMotion m = body.segmental_motion({.flexion_deg = 60});
  const SegmentalMotion generic = distribute(generic_spine_spec(), 40, 0, 0);
  const double ratio15 = m.joints[15].flexion / generic.joints[15].flexion;
  const double ratio0 = m.joints[0].flexion / generic.joints[0].flexion;
  EXPECT_NEAR(ratio15 / ratio0, 2.0, 1e-9);
}

}  // namespace
}  // namespace spinewatch::phantom
