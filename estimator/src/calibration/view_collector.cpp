#include "spinewatch/estimator/calibration/view_collector.hpp"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "calibration/camera_views.hpp"

namespace spinewatch {

const char* to_string(FrameVerdict verdict) {
  switch (verdict) {
    case FrameVerdict::NoBoard: return "no board";
    case FrameVerdict::TooFewCorners: return "too few corners";
    case FrameVerdict::Moving: return "moving";
    case FrameVerdict::SamePose: return "same pose";
    case FrameVerdict::Kept: return "kept";
  }
  return "?";
}

ViewCollector::ViewCollector(const CalibrationBoard& board, ViewCollectorOptions options)
    : board_(&board), options_(options) {}

double ViewCollector::displacement(const BoardDetection& a, const BoardDetection& b) {
  return calibration_detail::shared_corner_displacement(a.ids, a.pixels, b.ids, b.pixels);
}

FrameVerdict ViewCollector::offer(const cv::Mat& grey) {
  ++offered_;
  BoardDetection found = board_->detect(grey);
  if (found.empty()) {
    previous_.reset();
    steady_ = 0;
    return FrameVerdict::NoBoard;
  }
  ++with_board_;
  if (!board_->usable(found, options_.min_corners)) {
    previous_.reset();
    steady_ = 0;
    return FrameVerdict::TooFewCorners;
  }
  const bool still = previous_ && displacement(*previous_, found) < options_.steady_px;
  steady_ = still ? steady_ + 1 : 0;
  previous_ = found;
  if (steady_ < options_.steady_frames) return FrameVerdict::Moving;
  ++still_;
  if (options_.distinct_px > 0)
    for (const auto& k : kept_detections_)
      if (displacement(k, found) < options_.distinct_px) return FrameVerdict::SamePose;
  kept_detections_.push_back(std::move(found));
  frames_.push_back(grey.clone());
  return FrameVerdict::Kept;
}

std::string ViewCollector::summary() const {
  return fmt::format("{} frames, board in {}, still in {}, {} kept", offered_, with_board_, still_, kept());
}

}  // namespace spinewatch
