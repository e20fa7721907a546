// The pose's heading (body_model.hpp, CvsmPose::heading): the whole body,
// legs included, turned about the vertical through the hip joints, against
// the reference (the unturned pose's points turned by hand).
#include <gtest/gtest.h>

#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

TEST(CvsmHeadingModel, TurnedPoseIsTheUnturnedOneTurnedAboutTheHips) {
  const BodyModel model = other_subject();
  CvsmPose pose = bend(20, 5, 3);
  pose.translation = {12, -4, -7};
  pose.limbs.side[0].hip_flexion = 25;
  pose.limbs.side[1].knee = 30;
  pose.limbs.side[1].shoulder_abduction = 40;
  for (const double heading : {90.0, 137.0, 180.0, -60.0}) {
    CvsmPose turned = pose;
    turned.heading = heading;
    const SpinePose v0 = pose_vertebrae(model, generic_spine_spec(), pose);
    const SpinePose v1 = pose_vertebrae(model, generic_spine_spec(), turned);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(heading * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d pivot =
        model.neutral[kWaistIndex].body_center + 0.5 * (model.hip_left + model.hip_right) + pose.translation;
    for (std::size_t k = 0; k < kVertebraCount; ++k) {
      EXPECT_LT((v1[k].body_center - (pivot + R * (v0[k].body_center - pivot))).norm(), 1e-9) << heading << " " << k;
      EXPECT_LT((v1[k].q.toRotationMatrix() - R * v0[k].q.toRotationMatrix()).norm(), 1e-9) << heading << " " << k;
    }
    std::vector<Eigen::Vector3d> p0, p1;
    control_points(model, v0, p0, pose.limbs);
    control_points(model, v1, p1, turned.limbs, turned.heading);
    ASSERT_EQ(p0.size(), p1.size());
    for (std::size_t i = 0; i < p0.size(); ++i) {
      if (!model.in_chain[i / kControlPoints]) continue;
      EXPECT_LT((p1[i] - (pivot + R * (p0[i] - pivot))).norm(), 1e-9) << heading << " point " << i;
    }
  }
}

}  // namespace
}  // namespace spinewatch
