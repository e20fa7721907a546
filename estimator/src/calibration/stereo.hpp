#pragma once
// Internal to the calibration area: the two cameras' relative pose from
// every frame both saw the board in, and a still stretch of the board
// inside the views (the world frame when no placement was recorded).
#include <optional>
#include <utility>

#include <Eigen/Core>

#include "calibration/camera_views.hpp"

namespace spinewatch::calibration_detail {

// The lateral camera from the frontal: x_lateral = R · x_frontal + t (mm).
struct RelativePose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double rms_px = 0;  // over both cameras' corners of the shared views
  int views = 0;      // frames used: both cameras saw at least 6 of the same corners
};

// Frames (same index in both) in which both cameras saw at least 6 of the
// same corners.
int count_shared_views(const FrameObservations& frontal, const FrameObservations& lateral);

// cv::stereoCalibrate with both cameras' intrinsics held: one relative pose
// and a board pose per shared frame, fitted to all their corners at once.
// Nothing when fewer than `min_views` frames are shared.
Result<RelativePose> fit_relative_pose(const CalibrationBoard& board, const std::array<CameraModel, 2>& intrinsics,
                                       const std::array<const FrameObservations*, 2>& observed, int min_views,
                                       cv::Size image_size);

// The longest run of consecutive frames (at least 2) in which the board was
// found in every camera of `cameras` and moved less than `still_px` on
// average from one frame to the next in each; nothing when there is none.
// `motion_px` is the largest such move within the run.
struct StillStretch {
  int first = 0, last = 0;  // frame indices, inclusive
  double motion_px = 0;
};
std::optional<StillStretch> find_still_stretch(const std::vector<const FrameObservations*>& cameras, double still_px);

}  // namespace spinewatch::calibration_detail
