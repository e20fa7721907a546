#pragma once
// The live view's /state document (docs/state.schema.json): the latest
// posture the live view sampled, the setup aids (is the whole subject in
// view of each camera, where the backgrounds and the calibration came
// from) and the daemon's counters and rates.
#include <string>

#include "http/daemon_metrics.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"

namespace spinewatch {

// What does not change while the daemon runs.
struct StationInfo {
  std::string station;
  std::string source;           // the frame source, as in the hello line
  std::string calibration;      // the calibration file used, or "default rig"
  bool default_rig = false;
  BackgroundMode background_mode = BackgroundMode::Learn;  // silhouette.background
  bool relearn_available = false;  // POST /background/relearn has an effect
  double fps = 0;               // http.fps
  bool camera_pixels = false;   // http.camera_pixels
};

// `latest`: the last sample (null before the first); `now_ns` CLOCK_MONOTONIC.
std::string state_json(const StationInfo& station, const DaemonMetrics& metrics, const LiveSummary* latest,
                       std::int64_t now_ns);

}  // namespace spinewatch
