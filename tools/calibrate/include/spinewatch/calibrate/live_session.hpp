#pragma once
// Calibrating from live cameras: both cameras stream; each keeps the views
// of the board held at poses (ViewCollector) until both have enough, then
// — once the installer has placed the board where the subject will stand —
// the frames of the placement board held still in both. What comes out is
// what calibrate_station takes from recordings.
#include <array>
#include <chrono>
#include <functional>
#include <string>

#include "spinewatch/capture/camera.hpp"
#include "spinewatch/estimator/calibration/station_calibration.hpp"
#include "spinewatch/estimator/calibration/view_collector.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct LiveSessionOptions {
  int views = 40;             // views kept per camera (at least CalibrationLimits::min_views)
  int placement_frames = 8;   // still frames of the placement board per camera
  ViewCollectorOptions collector;
  std::chrono::milliseconds timeout{std::chrono::minutes(10)};  // per phase
  // Cameras whose intrinsics are given need no views.
  std::array<bool, 2> need_views = {true, true};
};

struct LiveSessionHooks {
  // A line of progress, when a count changes: "frontal: 7/12 views, lateral: 5/12".
  std::function<void(const std::string&)> progress;
  // Between the views and the placement: returns when the board is in
  // place (the command waits for Enter on a terminal).
  std::function<void()> before_placement;
};

struct LiveSession {
  std::array<CameraFrames, 2> frames;  // views and placement (no intrinsics)
  cv::Size size;
};

// `cameras` started; index 0 frontal, 1 lateral. An Error, naming what each
// camera saw, when a phase does not complete within the timeout or a
// camera stops.
Result<LiveSession> collect_live(std::array<Camera*, 2> cameras, const CalibrationBoard& board,
                                 const LiveSessionOptions& options, const LiveSessionHooks& hooks);

}  // namespace spinewatch
