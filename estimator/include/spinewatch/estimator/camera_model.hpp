#pragma once
// Pinhole camera with OpenCV's distortion model and conventions
// (docs/interfaces.md §2): x_cam = R · X_world + t, millimetres.
#include <array>
#include <string_view>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// OpenCV's distortion coefficients, in its order: k1 k2 p1 p2 k3 (the
// classic model), k4 k5 k6 (rational), s1 s2 s3 s4 (thin prism), τx τy
// (tilted sensor). A calibration with 4, 5, 8, 12 or 14 coefficients
// fills the first ones; the rest are zero, which is the same model.
inline constexpr std::size_t kMaxDistortion = 14;
inline constexpr std::array<int, 5> kDistortionLengths = {4, 5, 8, 12, 14};

struct CameraModel {
  Eigen::Matrix3d camera_matrix = Eigen::Matrix3d::Identity();
  std::array<double, kMaxDistortion> dist_coeffs{};
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  // The image size the calibration was made for (image_width, image_height
  // in calibration.yaml); 0 when the file does not say.
  int image_width = 0, image_height = 0;

  Eigen::Vector3d to_camera(const Eigen::Vector3d& world) const { return R * world + t; }
  Eigen::Vector3d centre_in_world() const { return -R.transpose() * t; }
  // Pixel coordinates of a world point, or nothing when it is behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& world) const;
  // The lens model alone: undistorted normalised coordinates (x/z, y/z in
  // the camera frame) to distorted ones, as cv::projectPoints computes them.
  Eigen::Vector2d distort(const Eigen::Vector2d& normalised) const;
  // Its inverse (what cv::undistortPoints gives, but solved to 1e-10 rather
  // than five fixed-point steps): the normalised coordinates of the ray
  // through a pixel; nothing where the lens model does not invert there
  // (far outside the calibrated field of view).
  std::optional<Eigen::Vector2d> normalised(const Eigen::Vector2d& pixel) const;
  // Unit ray (world frame) through a pixel, through the lens model; the
  // pinhole ray where the model does not invert.
  Eigen::Vector3d ray_through(const Eigen::Vector2d& pixel) const;
  bool has_distortion() const;
  // The coefficients as a calibration file holds them: the shortest of
  // OpenCV's lengths (5, 8, 12 or 14) that keeps every non-zero one.
  std::vector<double> distortion() const;
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
  // That rig in one phrase, for the warning that it is used.
  static constexpr std::string_view kDefaultRigSummary =
      "two ideal orthogonal cameras 2 m from the subject at 1.1 m height, 300 px focal length, 320x240, no distortion";
};

// calibration.yaml (OpenCV FileStorage): nodes `frontal` and `lateral`,
// each with camera_matrix 3×3, dist_coeffs 1×5, R 3×3, t 3×1 — or the keys
// of OpenCV's own calibration tools (docs/calibration.md, "Files from
// elsewhere"): Camera_Matrix / cameraMatrix, distortion_coefficients /
// Distortion_Coefficients with 4, 5, 8, 12 or 14 coefficients, and
// image_width / image_height.
Result<CameraRig> load_calibration(const std::filesystem::path& path);
// Writes the project's keys; dist_coeffs 1×5 unless a camera uses more of
// OpenCV's model; image_width / image_height when known.
Status save_calibration(const std::filesystem::path& path, const CameraRig& rig);

// One camera's intrinsics as OpenCV's calibration samples write them (the
// keys above at the top level of the file): camera_matrix, the distortion
// and the image size. R and t stay identity and zero.
Result<CameraModel> load_intrinsics(const std::filesystem::path& path);
// Writes one camera's intrinsics so that load_intrinsics reads them back:
// camera_matrix, distortion_coefficients and the image size.
Status save_intrinsics(const std::filesystem::path& path, const CameraModel& camera);

// A calibration made at one resolution does not fit a stream of another:
// an error naming the camera when image_width / image_height are known and
// differ from the stream's.
Status check_image_size(const CameraRig& rig, int width, int height);

}  // namespace spinewatch
