#pragma once
// Pinhole camera with OpenCV's distortion model and conventions
// (interfaces.md §2): x_cam = R · X_world + t, millimetres.
#include <array>
#include <filesystem>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct CameraModel {
  Eigen::Matrix3d camera_matrix = Eigen::Matrix3d::Identity();
  std::array<double, 5> dist_coeffs{};  // k1 k2 p1 p2 k3
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d to_camera(const Eigen::Vector3d& world) const { return R * world + t; }
  Eigen::Vector3d centre_in_world() const { return -R.transpose() * t; }
  // Pixel coordinates of a world point, or nothing when it is behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& world) const;
  // Unit ray (world frame) through a pixel, ignoring distortion.
  Eigen::Vector3d ray_through(const Eigen::Vector2d& pixel) const;
  bool has_distortion() const;
};

// The two orthogonal views of the station.
struct CameraRig {
  CameraModel frontal;
  CameraModel lateral;

  // The documented default (docs/calibration.md): two ideal pinhole cameras,
  // f = 300 px, principal point (160, 120), no distortion, 2000 mm from the
  // world Y axis at a height of 1100 mm; frontal on +X looking along −X,
  // lateral on +Z (the subject's right) looking along −Z.
  static CameraRig default_rig();
};

// calibration.yaml (OpenCV FileStorage): nodes `frontal` and `lateral`, each
// with camera_matrix 3×3, dist_coeffs 1×5, R 3×3, t 3×1.
Result<CameraRig> load_calibration(const std::filesystem::path& path);
Status save_calibration(const std::filesystem::path& path, const CameraRig& rig);

}  // namespace spinewatch
