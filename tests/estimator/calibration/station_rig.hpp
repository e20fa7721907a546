#pragma once
// A station as a real one is set up: cameras a little off their nominal
// places and aims, each lens with its own distortion — the truth that
// calibration from rendered boards must recover.
#include <Eigen/Geometry>

#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch::test {

// A camera at `centre` looking at `target`, image up along world +Y, then
// rolled about its axis.
inline CameraModel looking_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& target, double roll_deg,
                              double fx, double fy, double cx, double cy, std::array<double, 5> dist) {
  CameraModel cam;
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = (-Eigen::Vector3d::UnitY()).cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  cam.R = Eigen::AngleAxisd(roll_deg * 3.14159265358979323846 / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  cam.t = -cam.R * centre;
  cam.camera_matrix << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  for (std::size_t i = 0; i < 5; ++i) cam.dist_coeffs[i] = dist[i];
  return cam;
}

// The frontal camera stands on the world X axis (z = 0): the world frame
// calibration recovers puts X towards it, so the truth must too.
inline CameraRig station_rig() {
  CameraRig rig;
  rig.frontal = looking_at({2100, 1080, 0}, {0, 1000, 0}, 0.7, 305, 303, 163, 118, {-0.18, 0.06, 0.0012, -0.0008, 0});
  rig.lateral = looking_at({60, 1130, 1950}, {-20, 1020, 0}, -0.5, 298, 297, 158, 122, {-0.15, 0.04, -0.001, 0.0006, 0});
  return rig;
}

}  // namespace spinewatch::test
