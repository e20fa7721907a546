#pragma once
// The station's world frame (interfaces.md §1) placed in a foreign
// calibration's frame (docs/import.md, "World frame"): Y up — given, or
// the mean "up" of the cameras' upright images —, X horizontal from the
// point the two cameras look at towards the frontal camera, Z = X × Y,
// origin on the floor below that point (`camera_height_mm` below the
// cameras' mean height, the files carrying no floor).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/estimator/calibration/foreign_calibration.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::import {

struct WorldFrame {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // rows: X, Y, Z of the station in the file's frame
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();    // in the file's frame, mm
  std::vector<std::string> report;                     // how it was chosen, a line each

  // A point of the file's frame in the station's frame.
  Eigen::Vector3d to_station(const Eigen::Vector3d& file_point) const { return axes * (file_point - origin); }
  // x_cam = R·X_file + t becomes x_cam = R'·X_station + t'.
  CameraModel to_station(const CameraModel& camera) const;
};

// "X,Y,Z", a direction in the calibration's frame (need not be unit).
Result<Eigen::Vector3d> parse_up(const std::string& text);

// Each usable camera's up as its upright image shows it (caliscope's
// rotation_count turns the image first); their normalised mean.
Result<Eigen::Vector3d> estimate_up(const CameraArray& array, std::vector<std::string>& report);

// The frame for this rig; `up` in the file's frame (unit). An error when
// the frontal camera stands straight above or below the look-at point.
Result<WorldFrame> choose_world_frame(const CameraRig& file_rig, const Eigen::Vector3d& up, double camera_height_mm);

}  // namespace spinewatch::import
