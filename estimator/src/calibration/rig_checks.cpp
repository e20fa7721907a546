#include "spinewatch/estimator/calibration/rig_checks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace spinewatch {

std::vector<std::string> intrinsics_problems(const std::string& name, const CameraModel& camera,
                                             const RigRules& rules) {
  std::vector<std::string> problems;
  const double fx = camera.camera_matrix(0, 0), fy = camera.camera_matrix(1, 1);
  const double cx = camera.camera_matrix(0, 2), cy = camera.camera_matrix(1, 2);
  if (!rules.free_aspect && fx > 0 && std::abs(fy / fx - 1) > rules.max_aspect_error)
    problems.push_back(fmt::format(
        "{} camera: fy/fx = {:.3f} (fx {:.1f}, fy {:.1f} px), more than {:.0f} % from 1: webcams have square "
        "pixels, so the views did not pin the focal length; add views of the board tilted 20–45° each way and "
        "near the image's corners (or, for a lens that does stretch the image, --aspect free)",
        name, fy / fx, fx, fy, 100 * rules.max_aspect_error));
  if (camera.image_width > 0 && camera.image_height > 0) {
    const double w = camera.image_width, h = camera.image_height;
    if (cx < w / 3 || cx > 2 * w / 3 || cy < h / 3 || cy > 2 * h / 3)
      problems.push_back(fmt::format(
          "{} camera: principal point ({:.1f}, {:.1f}) px lies outside the central third of the {}x{} image "
          "({:.0f}–{:.0f}, {:.0f}–{:.0f}): a lens centre that far off means views that did not pin it; add views "
          "with the board near each corner and edge of the image",
          name, cx, cy, camera.image_width, camera.image_height, w / 3, 2 * w / 3, h / 3, 2 * h / 3));
  }
  return problems;
}

std::vector<std::string> extrinsics_problems(const CameraRig& rig, const RigRules& rules) {
  std::vector<std::string> problems;
  const Eigen::Vector3d a = rig.frontal.centre_in_world(), b = rig.lateral.centre_in_world();
  const double distance = (a - b).norm();
  if (distance < rules.min_distance_mm)
    problems.push_back(fmt::format(
        "the cameras stand {:.0f} mm apart, closer than {:.0f} mm: two cameras of one station look at the "
        "subject from the front and the side, metres apart; the relative pose is wrong (a wrong --square-mm, "
        "or the same camera twice)",
        distance, rules.min_distance_mm));
  const Eigen::Vector3d axis_a = rig.frontal.R.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d axis_b = rig.lateral.R.transpose() * Eigen::Vector3d::UnitZ();
  const double angle = std::acos(std::clamp(axis_a.dot(axis_b), -1.0, 1.0)) * 180 / std::numbers::pi;
  if (angle < rules.min_axis_angle_deg)
    problems.push_back(fmt::format(
        "the cameras' optical axes are {:.1f}° apart, less than {:.0f}°: both look the same way, so the "
        "lateral view adds no depth; turn the lateral camera to the subject's side",
        angle, rules.min_axis_angle_deg));
  return problems;
}

std::vector<std::string> rig_problems(const CameraRig& rig, const RigRules& rules) {
  std::vector<std::string> problems = intrinsics_problems("frontal", rig.frontal, rules);
  for (auto& p : intrinsics_problems("lateral", rig.lateral, rules)) problems.push_back(std::move(p));
  for (auto& p : extrinsics_problems(rig, rules)) problems.push_back(std::move(p));
  return problems;
}

}  // namespace spinewatch
