#pragma once
// Internal to the calibration area: one camera's board observations and
// its intrinsics from them.
#include <array>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/calibration/station_calibration.hpp"

namespace spinewatch::calibration_detail {

// Mean displacement (px) of the corners two board observations share (by
// corner id), from a to b; infinite when they share none, or fewer than
// half of b's: a different view of the board, not the same one moved.
double shared_corner_displacement(const std::vector<int>& ids_a, const std::vector<cv::Point2f>& pixels_a,
                                  const std::vector<int>& ids_b, const std::vector<cv::Point2f>& pixels_b);

struct Observation {
  int frame = 0;
  std::vector<int> ids;
  std::vector<cv::Point2f> pixels;
};

// The board in every frame: a usable observation (enough corners, not on
// one line) or nothing, in frame order; the counts of what was seen, and
// the markers' colours, into `report`.
using FrameObservations = std::vector<std::optional<Observation>>;
FrameObservations observe_frames(const CalibrationBoard& board, const std::vector<cv::Mat>& frames,
                                 const CalibrationLimits& limits, CameraReport& report);

// The distinct views among them (a board held still for a second gives
// thirty copies of one pose; only the first counts).
std::vector<Observation> distinct_views(const FrameObservations& frames, const CalibrationLimits& limits,
                                        CameraReport& report);

struct IntrinsicsFit {
  CameraModel camera;  // camera_matrix and dist_coeffs (k1 k2 p1 p2; k3 = 0)
  double rms_px = 0;
  std::array<double, 8> sigma{};  // 1-σ of fx fy cx cy k1 k2 p1 p2 (cv::calibrateCamera's stdDeviationsIntrinsics)
  double max_tilt_deg = 0;        // the most a view's board was tilted from facing the camera
  std::vector<ViewError> views;
};

// What part of the image the views' corners covered: of a 3×3 grid of the
// image, the cells with a corner in them (bit 3·row + column).
unsigned covered_cells(const std::vector<Observation>& views, cv::Size image_size);

// cv::calibrateCamera over the views; an Error when OpenCV gives up.
Result<IntrinsicsFit> fit_intrinsics(const CalibrationBoard& board, const std::vector<Observation>& views,
                                     cv::Size image_size);

// RMS distance (px) between `pixels` and the board corners `ids` projected
// with the pose (rvec, tvec) through the camera's intrinsics.
double reprojection_rms(const CalibrationBoard& board, const CameraModel& camera, const std::vector<int>& ids,
                        const std::vector<cv::Point2f>& pixels, const cv::Mat& rvec, const cv::Mat& tvec);

cv::Mat camera_matrix_cv(const CameraModel& camera);
cv::Mat dist_coeffs_cv(const CameraModel& camera);

}  // namespace spinewatch::calibration_detail
