// The rules no real station breaks, each with its message: what calibrate
// refuses and check refuses alike.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "spinewatch/estimator/calibration/rig_checks.hpp"

namespace spinewatch {
namespace {

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems)
    if (p.find(text) != std::string::npos) return true;
  return false;
}

TEST(RigChecks, TheDefaultRigPasses) { EXPECT_TRUE(rig_problems(CameraRig::default_rig(), {}).empty()); }

TEST(RigChecks, AStretchedFocalLengthIsRefusedUnlessTheAspectIsFree) {
  CameraModel cam = CameraRig::default_rig().lateral;
  cam.camera_matrix(1, 1) = 0.86 * cam.camera_matrix(0, 0);
  const auto problems = intrinsics_problems("lateral", cam, {});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("lateral camera: fy/fx = 0.860 (fx 300.0, fy 258.0 px), more than 5 % from 1"),
            std::string::npos)
      << problems[0];
  EXPECT_TRUE(intrinsics_problems("lateral", cam, {.free_aspect = true}).empty());
  cam.camera_matrix(1, 1) = 1.04 * cam.camera_matrix(0, 0);
  EXPECT_TRUE(intrinsics_problems("lateral", cam, {}).empty());
}

TEST(RigChecks, ACentreOutsideTheCentralThirdIsRefused) {
  CameraModel cam = CameraRig::default_rig().frontal;
  cam.image_width = 320;
  cam.image_height = 240;
  cam.camera_matrix(0, 2) = 100;  // the central third is 106.7–213.3
  const auto problems = intrinsics_problems("frontal", cam, {});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("frontal camera: principal point (100.0, 120.0) px lies outside the central third of "
                             "the 320x240 image"),
            std::string::npos)
      << problems[0];
  cam.camera_matrix(0, 2) = 110;
  EXPECT_TRUE(intrinsics_problems("frontal", cam, {}).empty());
}

TEST(RigChecks, CoLocatedCamerasAreRefused) {
  CameraRig rig = CameraRig::default_rig();
  rig.lateral = rig.frontal;  // the same camera twice
  const auto problems = extrinsics_problems(rig, {});
  EXPECT_TRUE(mentions(problems, "the cameras stand 0 mm apart, closer than 300 mm")) << problems.size();
  EXPECT_TRUE(mentions(problems, "the cameras' optical axes are 0.0° apart, less than 20°")) << problems.size();
}

TEST(RigChecks, CamerasLookingTheSameWayAreRefused) {
  CameraRig rig = CameraRig::default_rig();
  // The lateral camera turned to look along the frontal's axis, 15° off it,
  // from a metre to the side.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(15 * 3.14159265358979 / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  rig.lateral.R = rig.frontal.R * turn;
  rig.lateral.t = -rig.lateral.R * Eigen::Vector3d(2000, 1100, 1000);
  const auto problems = extrinsics_problems(rig, {});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("the cameras' optical axes are 15.0° apart, less than 20°"), std::string::npos)
      << problems[0];
}

}  // namespace
}  // namespace spinewatch
