#include "calibration/stereo.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace spinewatch::calibration_detail {
namespace {

constexpr int kMinSharedCorners = 6;

// The corners both observations hold, in the frontal's order.
struct SharedCorners {
  std::vector<cv::Point3f> board;
  std::vector<cv::Point2f> pixels[2];
};

SharedCorners shared_corners(const CalibrationBoard& board, const Observation& a, const Observation& b) {
  std::map<int, cv::Point2f> in_b;
  for (std::size_t i = 0; i < b.ids.size(); ++i) in_b[b.ids[i]] = b.pixels[i];
  SharedCorners shared;
  for (std::size_t i = 0; i < a.ids.size(); ++i)
    if (auto it = in_b.find(a.ids[i]); it != in_b.end()) {
      shared.board.push_back(board.corner(a.ids[i]));
      shared.pixels[0].push_back(a.pixels[i]);
      shared.pixels[1].push_back(it->second);
    }
  return shared;
}

int shared_count(const Observation& a, const Observation& b) {
  int n = 0;
  for (int id : a.ids) n += std::count(b.ids.begin(), b.ids.end(), id) > 0;
  return n;
}

}  // namespace

int count_shared_views(const FrameObservations& frontal, const FrameObservations& lateral) {
  int views = 0;
  for (std::size_t i = 0; i < std::min(frontal.size(), lateral.size()); ++i)
    if (frontal[i] && lateral[i] && shared_count(*frontal[i], *lateral[i]) >= kMinSharedCorners) ++views;
  return views;
}

Result<RelativePose> fit_relative_pose(const CalibrationBoard& board, const std::array<CameraModel, 2>& intrinsics,
                                       const std::array<const FrameObservations*, 2>& observed, int min_views,
                                       cv::Size image_size) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image[2];
  const std::size_t frames = std::min(observed[0]->size(), observed[1]->size());
  for (std::size_t i = 0; i < frames; ++i) {
    const auto& a = (*observed[0])[i];
    const auto& b = (*observed[1])[i];
    if (!a || !b) continue;
    SharedCorners shared = shared_corners(board, *a, *b);
    if (static_cast<int>(shared.board.size()) < kMinSharedCorners) continue;
    object.push_back(std::move(shared.board));
    for (int c = 0; c < 2; ++c) image[c].push_back(std::move(shared.pixels[c]));
  }
  if (static_cast<int>(object.size()) < min_views)
    return Error{fmt::format("{} frames show the board to both cameras (at least {} of the same corners); {} are "
                             "needed for the relative pose from them",
                             object.size(), kMinSharedCorners, min_views)};
  RelativePose pose;
  pose.views = static_cast<int>(object.size());
  cv::Mat K[2] = {camera_matrix_cv(intrinsics[0]), camera_matrix_cv(intrinsics[1])};
  cv::Mat dist[2] = {dist_coeffs_cv(intrinsics[0]), dist_coeffs_cv(intrinsics[1])};
  cv::Mat R, T, E, F;
  try {
    pose.rms_px = cv::stereoCalibrate(object, image[0], image[1], K[0], dist[0], K[1], dist[1], image_size, R, T, E, F,
                                      cv::CALIB_FIX_INTRINSIC,
                                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-10));
  } catch (const cv::Exception& e) {
    return Error{fmt::format("cv::stereoCalibrate failed ({})", e.err)};
  }
  cv::cv2eigen(R, pose.R);
  cv::cv2eigen(T, pose.t);
  return pose;
}

std::optional<StillStretch> find_still_stretch(const std::vector<const FrameObservations*>& cameras, double still_px) {
  if (cameras.empty()) return std::nullopt;
  std::size_t frames = cameras[0]->size();
  for (const auto* c : cameras) frames = std::min(frames, c->size());
  std::optional<StillStretch> best;
  std::optional<StillStretch> run;
  auto seen_in_all = [&](std::size_t i) {
    return std::all_of(cameras.begin(), cameras.end(), [&](const auto* c) { return (*c)[i].has_value(); });
  };
  for (std::size_t i = 1; i < frames; ++i) {
    double motion = 0;
    bool still = seen_in_all(i) && seen_in_all(i - 1);
    for (const auto* c : cameras) {
      if (!still) break;
      const Observation& a = *(*c)[i - 1];
      const Observation& b = *(*c)[i];
      const double d = shared_corner_displacement(a.ids, a.pixels, b.ids, b.pixels);
      motion = std::max(motion, d);
      still = d < still_px;
    }
    if (!still) {
      run.reset();
      continue;
    }
    if (!run) run = StillStretch{static_cast<int>(i - 1), static_cast<int>(i - 1), 0};
    run->last = static_cast<int>(i);
    run->motion_px = std::max(run->motion_px, motion);
    if (!best || run->last - run->first > best->last - best->first ||
        (run->last - run->first == best->last - best->first && run->motion_px < best->motion_px))
      best = run;
  }
  return best;
}

}  // namespace spinewatch::calibration_detail
