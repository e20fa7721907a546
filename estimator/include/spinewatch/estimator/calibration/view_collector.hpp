#pragma once
// Calibrating from live cameras (docs/calibration.md, "From live cameras"):
// which frames of one camera's stream are worth keeping. A frame is kept
// when the board is found with enough corners (not all on one line), held
// still — its corners moved less than `steady_px` since the previous frame
// for `steady_frames` frames in a row, so the exposure is not smeared by
// motion — and at a new pose: its corners at least `distinct_px` on
// average from those of every view kept so far.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/calibration/board.hpp"

namespace spinewatch {

struct ViewCollectorOptions {
  int min_corners = 8;
  double steady_px = 0.75;
  int steady_frames = 2;
  // 0: every steady frame is kept (the placement board, which lies still
  // and whose frames only average the noise).
  double distinct_px = 12.0;
};

enum class FrameVerdict { NoBoard, TooFewCorners, Moving, SamePose, Kept };
const char* to_string(FrameVerdict verdict);

class ViewCollector {
 public:
  // `board` must outlive the collector.
  ViewCollector(const CalibrationBoard& board, ViewCollectorOptions options);

  // Looks at one frame (grey CV_8U); keeps a copy of it when it is a view.
  FrameVerdict offer(const cv::Mat& grey);

  int kept() const { return static_cast<int>(frames_.size()); }
  const std::vector<cv::Mat>& frames() const { return frames_; }
  // What the frames offered so far showed, for progress and refusals:
  // "412 frames, board in 230, 118 still, 12 kept".
  std::string summary() const;

  // Mean distance (px) between the corners two detections share; infinite
  // when they share fewer than half of `b`'s corners.
  static double displacement(const BoardDetection& a, const BoardDetection& b);

 private:
  const CalibrationBoard* board_;
  ViewCollectorOptions options_;
  std::optional<BoardDetection> previous_;
  int steady_ = 0;  // frames in a row the board has been still
  std::vector<BoardDetection> kept_detections_;
  std::vector<cv::Mat> frames_;
  int offered_ = 0, with_board_ = 0, still_ = 0;
};

}  // namespace spinewatch
