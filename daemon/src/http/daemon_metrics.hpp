#pragma once
// Everything the daemon counts, gathered in one value for /metrics
// (Prometheus text, metrics_text.hpp) and /state (state_json.hpp). Each
// part is read from its owner's atomics; nothing here is kept twice.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "http/latency_histogram.hpp"
#include "http/live_view.hpp"
#include "mqtt/mqtt_publisher.hpp"
#include "pipeline/pipeline.hpp"
#include "publish/publisher.hpp"

namespace spinewatch {

struct HttpStats {
  std::uint64_t connections = 0;        // open now
  std::uint64_t connections_total = 0;  // accepted since start
  std::uint64_t rejected = 0;           // refused: max_connections were open
  std::uint64_t timed_out = 0;          // dropped: a request or a write did not complete within timeout_s
  std::uint64_t bad_requests = 0;       // malformed or too large: answered 400/413/431 (or cut) and closed
  std::uint64_t requests = 0;           // answered
  std::uint64_t stream_viewers = 0;     // /stream connections now
  std::uint64_t stream_frames = 0;      // JPEG parts written to viewers
  std::uint64_t stream_frames_skipped = 0;  // a viewer still writing the last one got the next newer one instead
  std::uint64_t auth_failures = 0;      // requests answered 401: no or a wrong bearer token
  std::uint64_t tls_failures = 0;       // connections whose TLS handshake failed (plain text, no or a foreign certificate)
};

// Postures by state since start, and how often tracking was lost.
struct PostureCounts {
  std::array<std::uint64_t, 3> by_state{};  // indexed by TrackingState: init, tracking, lost
  std::uint64_t tracking_lost = 0;          // tracking → lost transitions
};

// A recording with ground truth (the phantom's): how far the tracked
// postures are from it, running means in mm (docs/daemon.md, "Live view").
struct TruthScoreStats {
  std::uint64_t pairs = 0;               // tracked pairs scored
  std::uint64_t pairs_not_tracking = 0;  // pairs with a truth but no tracked posture (init, lost)
  double vertebrae_mean_mm = 0;          // every vertebra's body centre, mean over vertebrae and pairs
  double neck_mean_mm = 0, waist_mean_mm = 0;
  double last_vertebrae_mm = 0;  // the last scored pair's
};

struct DaemonMetrics {
  PipelineStats pipeline;
  PublisherStats publisher;
  PostureCounts postures;
  BackgroundCounts background;  // both views' background updates, re-learns, bootstraps (as in the stream's stats)
  LatencyHistogram::Counts latency;
  LiveViewStats live;
  HttpStats http;
  std::optional<MqttStats> mqtt;  // with [mqtt] url set (docs/fleet.md)
  std::optional<TruthScoreStats> truth;  // replaying a recording with ground_truth.ndjson
  double pairs_per_s = 0;  // over the last second
  double uptime_s = 0;
};

// Prometheus text exposition format 0.0.4 (names: spinewatch_ prefix,
// _total for counters, _seconds for times; docs/daemon.md lists them).
std::string metrics_text(const DaemonMetrics& m);

}  // namespace spinewatch
