#pragma once
// The daemon's own counts of what the estimator produced, for /metrics,
// /state and the status line: postures by state, tracking losses, the
// backgrounds' updates, the latency histogram and the last state. The
// estimator thread writes (relaxed atomics); any thread reads.
#include <array>
#include <atomic>
#include <cstdint>

#include "http/daemon_metrics.hpp"
#include "http/latency_histogram.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

class PostureCounters {
 public:
  void observe(const Posture& posture);  // estimator thread
  void add_metrics(DaemonMetrics& metrics) const;
  TrackingState last_state() const { return static_cast<TrackingState>(last_state_.load(std::memory_order_relaxed)); }

 private:
  LatencyHistogram latency_;
  std::array<std::atomic<std::uint64_t>, 3> by_state_{};
  std::atomic<std::uint64_t> tracking_lost_{0};
  TrackingState previous_state_ = TrackingState::Lost;  // estimator thread only
  std::atomic<int> last_state_{static_cast<int>(TrackingState::Lost)};
  std::atomic<std::uint64_t> background_updates_{0}, background_relearns_{0}, background_bootstraps_{0};
};

}  // namespace spinewatch
