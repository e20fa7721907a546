#include "calibration/camera_views.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace spinewatch::calibration_detail {
namespace {

// A view is left out of the intrinsics when its error is over 3× the
// median view's and over this many pixels at 320 pixels wide.
constexpr double kLeftOutFloorPx = 0.3;

double displacement(const Observation& a, const Observation& b) {
  return shared_corner_displacement(a.ids, a.pixels, b.ids, b.pixels);
}

}  // namespace

double shared_corner_displacement(const std::vector<int>& ids_a, const std::vector<cv::Point2f>& pixels_a,
                                  const std::vector<int>& ids_b, const std::vector<cv::Point2f>& pixels_b) {
  std::map<int, cv::Point2f> at;
  for (std::size_t i = 0; i < ids_a.size(); ++i) at[ids_a[i]] = pixels_a[i];
  double sum = 0;
  int shared = 0;
  for (std::size_t i = 0; i < ids_b.size(); ++i)
    if (auto it = at.find(ids_b[i]); it != at.end()) {
      sum += cv::norm(it->second - pixels_b[i]);
      ++shared;
    }
  if (shared == 0 || 2 * shared < static_cast<int>(ids_b.size())) return INFINITY;
  return sum / shared;
}

cv::Mat camera_matrix_cv(const CameraModel& camera) {
  cv::Mat K;
  cv::eigen2cv(camera.camera_matrix, K);
  return K;
}

cv::Mat dist_coeffs_cv(const CameraModel& camera) { return cv::Mat(camera.distortion(), true).reshape(1, 1); }

FrameObservations observe_frames(const CalibrationBoard& board, const std::vector<cv::Mat>& frames,
                                 const CalibrationLimits& limits, CameraReport& report) {
  FrameObservations observed(frames.size());
  report.frames = static_cast<int>(frames.size());
  bool inverted = false;  // the colours of the last board found, tried first
  for (std::size_t i = 0; i < frames.size(); ++i) {
    BoardDetection found = board.detect(frames[i], inverted);
    report.max_markers = std::max(report.max_markers, found.markers);
    if (found.empty()) continue;
    inverted = found.inverted;
    ++report.frames_with_board;
    ++(found.inverted ? report.frames_white_on_black : report.frames_black_on_white);
    if (!board.usable(found, limits.min_corners)) continue;
    ++report.frames_usable;
    observed[i] = Observation{static_cast<int>(i), std::move(found.ids), std::move(found.pixels)};
  }
  return observed;
}

std::vector<Observation> distinct_views(const FrameObservations& frames, const CalibrationLimits& limits,
                                        CameraReport& report) {
  std::vector<Observation> views;
  for (const auto& o : frames) {
    if (!o) continue;
    if (!views.empty() && displacement(views.back(), *o) < limits.distinct_px) continue;
    views.push_back(*o);
  }
  double corners = 0;
  for (const auto& v : views) corners += double(v.ids.size());
  report.distinct_views = static_cast<int>(views.size());
  report.mean_corners = views.empty() ? 0 : corners / double(views.size());
  return views;
}

unsigned covered_cells(const std::vector<Observation>& views, cv::Size image_size) {
  unsigned cells = 0;
  for (const auto& v : views)
    for (const auto& p : v.pixels) {
      const int column = std::clamp(int(3 * p.x / float(image_size.width)), 0, 2);
      const int row = std::clamp(int(3 * p.y / float(image_size.height)), 0, 2);
      cells |= 1u << (3 * row + column);
    }
  return cells;
}

double reprojection_rms(const CalibrationBoard& board, const CameraModel& camera, const std::vector<int>& ids,
                        const std::vector<cv::Point2f>& pixels, const cv::Mat& rvec, const cv::Mat& tvec) {
  std::vector<cv::Point2f> projected;
  cv::projectPoints(board.object_points(ids), rvec, tvec, camera_matrix_cv(camera), dist_coeffs_cv(camera),
                    projected);
  double sum = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const cv::Point2f d = projected[i] - pixels[i];
    sum += d.dot(d);
  }
  return pixels.empty() ? 0 : std::sqrt(sum / double(pixels.size()));
}

Result<IntrinsicsFit> fit_intrinsics(const CalibrationBoard& board, const std::vector<Observation>& views,
                                     cv::Size image_size) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const auto& v : views) {
    object.push_back(board.object_points(v.ids));
    image.push_back(v.pixels);
  }
  IntrinsicsFit fit;
  std::vector<bool> kept(views.size(), true);
  // Twice at most: a view far worse than the others (a corner taken for its
  // neighbour, a blurred frame) is left out of the second fit, and the
  // report says so; the error of every view is still reported.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::vector<cv::Point3f>> object;
    std::vector<std::vector<cv::Point2f>> image;
    for (std::size_t i = 0; i < views.size(); ++i)
      if (kept[i]) {
        object.push_back(board.object_points(views[i].ids));
        image.push_back(views[i].pixels);
      }
    cv::Mat K, dist, deviations, extrinsic_deviations, view_errors;
    std::vector<cv::Mat> rvecs, tvecs;
    try {
      // OpenCV's classic model with k3 held at 0 (k1 k2 p1 p2): what the
      // narrow lenses of these cameras need; k3 and the rational and
      // thin-prism terms would fit the noise of a 320×240 image.
      fit.rms_px = cv::calibrateCamera(object, image, image_size, K, dist, rvecs, tvecs, deviations,
                                       extrinsic_deviations, view_errors, cv::CALIB_FIX_K3,
                                       cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
    } catch (const cv::Exception& e) {
      return Error{fmt::format("cv::calibrateCamera failed ({})", e.err)};
    }
    cv::cv2eigen(K, fit.camera.camera_matrix);
    fit.camera.dist_coeffs = {};
    for (int i = 0; i < std::min<int>(dist.rows * dist.cols, int(kMaxDistortion)); ++i)
      fit.camera.dist_coeffs[static_cast<std::size_t>(i)] = dist.at<double>(i);
    // stdDeviationsIntrinsics: fx fy cx cy k1 k2 p1 p2 k3 …
    for (int i = 0; i < 8 && i < deviations.rows * deviations.cols; ++i)
      fit.sigma[static_cast<std::size_t>(i)] = deviations.at<double>(i);
    fit.max_tilt_deg = 0;
    for (const cv::Mat& r : rvecs) {
      cv::Mat R;
      cv::Rodrigues(r, R);
      // The board's normal (its z axis) against the line of sight (the camera's z).
      const double cosine = std::abs(R.at<double>(2, 2));
      fit.max_tilt_deg = std::max(fit.max_tilt_deg, std::acos(std::min(cosine, 1.0)) * 180.0 / std::numbers::pi);
    }
    fit.views.clear();
    std::vector<double> errors;
    for (std::size_t i = 0, k = 0; i < views.size(); ++i) {
      ViewError e{views[i].frame, static_cast<int>(views[i].ids.size()), 0, !kept[i]};
      if (kept[i]) {
        e.rms_px = reprojection_rms(board, fit.camera, views[i].ids, views[i].pixels, rvecs[k], tvecs[k]);
        errors.push_back(e.rms_px);
        ++k;
      } else {
        // Its pose with the final intrinsics, for the report.
        cv::Mat rvec, tvec;
        cv::solvePnP(board.object_points(views[i].ids), views[i].pixels, K, dist, rvec, tvec);
        e.rms_px = reprojection_rms(board, fit.camera, views[i].ids, views[i].pixels, rvec, tvec);
      }
      fit.views.push_back(e);
    }
    if (pass == 1) break;
    std::vector<double> sorted = errors;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    // The floor is in pixels of a 320-pixel-wide image and scales with the
    // width (as the still board's motion does): a corner taken for its
    // neighbour is off by a square, many pixels at any size, while the
    // blur of a hand-held board grows with the resolution. A fixed 0.3 px
    // at 1280 wide leaves out sharp views of a moving board, and with
    // them what little pins a loosely viewed camera's intrinsics.
    const double floor_px = kLeftOutFloorPx * image_size.width / 320.0;
    const double limit = std::max(3 * sorted[sorted.size() / 2], floor_px);
    bool dropped = false;
    for (std::size_t i = 0; i < views.size(); ++i)
      if (fit.views[i].rms_px > limit && views.size() - std::size_t(std::count(kept.begin(), kept.end(), false)) > 3) {
        kept[i] = false;
        dropped = true;
      }
    if (!dropped) break;
  }
  return fit;
}

}  // namespace spinewatch::calibration_detail
