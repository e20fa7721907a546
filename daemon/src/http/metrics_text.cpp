#include <fmt/format.h>

#include "http/daemon_metrics.hpp"

namespace spinewatch {
namespace {

// One metric family: HELP, TYPE, then its samples.
class Family {
 public:
  Family(std::string& out, std::string_view name, std::string_view type, std::string_view help)
      : out_(out), name_(name) {
    fmt::format_to(std::back_inserter(out_), "# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
  }
  Family& sample(double value, std::string_view labels = {}, std::string_view suffix = {}) {
    if (labels.empty())
      fmt::format_to(std::back_inserter(out_), "{}{} {}\n", name_, suffix, value);
    else
      fmt::format_to(std::back_inserter(out_), "{}{}{{{}}} {}\n", name_, suffix, labels, value);
    return *this;
  }
  Family& sample(std::uint64_t value, std::string_view labels = {}) {
    if (labels.empty())
      fmt::format_to(std::back_inserter(out_), "{} {}\n", name_, value);
    else
      fmt::format_to(std::back_inserter(out_), "{}{{{}}} {}\n", name_, labels, value);
    return *this;
  }

 private:
  std::string& out_;
  std::string_view name_;
};

constexpr const char* kCamera[2] = {"camera=\"frontal\"", "camera=\"lateral\""};

// [mqtt] (docs/fleet.md): only while MQTT is configured.
void mqtt_metrics(std::string& out, const MqttStats& q) {
  Family(out, "spinewatch_mqtt_connected", "gauge", "1 while the link to the MQTT broker is up.")
      .sample(std::uint64_t{q.connected ? 1u : 0u});
  Family(out, "spinewatch_mqtt_outbox_messages", "gauge",
         "Summaries and alerts in the persistent outbox, waiting for the broker's acknowledgement.")
      .sample(q.outbox_messages);
  Family(out, "spinewatch_mqtt_published_total", "counter",
         "MQTT messages the broker has (QoS 1: acknowledged; QoS 0: written to the connection), by topic.")
      .sample(q.published_status, "topic=\"status\"")
      .sample(q.published_summary, "topic=\"summary\"")
      .sample(q.published_alert, "topic=\"alert\"")
      .sample(q.published_posture, "topic=\"posture\"");
  Family(out, "spinewatch_mqtt_dropped_total", "counter", "MQTT messages dropped, by reason.")
      .sample(q.dropped_disconnected, "reason=\"disconnected\"")
      .sample(q.dropped_queue_full, "reason=\"queue_full\"")
      .sample(q.dropped_outbox_full, "reason=\"outbox_full\"")
      .sample(q.dropped_handoff_full, "reason=\"handoff_full\"")
      .sample(q.dropped_outbox_error, "reason=\"outbox_error\"");
  Family(out, "spinewatch_mqtt_reconnects_total", "counter", "Links to the MQTT broker made again after an outage.")
      .sample(q.reconnects);
  Family(out, "spinewatch_mqtt_connect_failures_total", "counter", "Failed connection attempts to the MQTT broker, by reason.")
      .sample(q.failed_auth, "reason=\"auth\"")
      .sample(q.failed_tls, "reason=\"tls\"")
      .sample(q.failed_network, "reason=\"network\"");
}

// The source and the estimator: pairs, frames, cameras, postures, backgrounds.
void pipeline_metrics(std::string& out, const DaemonMetrics& m) {
  const auto& p = m.pipeline;
  Family(out, "spinewatch_pairs_total", "counter", "Frame pairs taken from the source.").sample(p.pairs);
  Family(out, "spinewatch_pairs_processed_total", "counter", "Frame pairs the estimator turned into postures.")
      .sample(p.pairs_processed);
  Family(out, "spinewatch_pairs_dropped_total", "counter", "Frame pairs dropped, by reason.")
      .sample(p.pairs_dropped, "reason=\"estimator_behind\"");
  Family(out, "spinewatch_frames_total", "counter", "Frames delivered, per camera.")
      .sample(p.source.camera[0].frames, kCamera[0])
      .sample(p.source.camera[1].frames, kCamera[1]);
  Family(out, "spinewatch_frames_lost_total", "counter",
         "Frames that never became part of a pair (unpaired, driver errors, sequence gaps, pair queue overflow).")
      .sample(p.source.frames_lost);
  Family(out, "spinewatch_camera_restarts_total", "counter", "Cameras reopened after a device loss, per camera.")
      .sample(p.source.camera[0].restarts, kCamera[0])
      .sample(p.source.camera[1].restarts, kCamera[1]);
  Family(out, "spinewatch_camera_losses_total", "counter", "Times a camera went away (unplugged, disconnected), per camera.")
      .sample(p.source.camera[0].losses, kCamera[0])
      .sample(p.source.camera[1].losses, kCamera[1]);
  Family(out, "spinewatch_postures_total", "counter", "Postures published, by tracking state.")
      .sample(m.postures.by_state[0], "state=\"init\"")
      .sample(m.postures.by_state[1], "state=\"tracking\"")
      .sample(m.postures.by_state[2], "state=\"lost\"");
  Family(out, "spinewatch_tracking_lost_total", "counter", "Times tracking was lost (a tracking pair followed by a lost one).")
      .sample(m.postures.tracking_lost);

  Family(out, "spinewatch_background_events_total", "counter",
         "Background adaptation passes, whole re-learns and bootstraps, both views together.")
      .sample(m.background.updates, "event=\"update\"")
      .sample(m.background.relearns, "event=\"relearn\"")
      .sample(m.background.bootstraps, "event=\"bootstrap\"");
}

void latency_metrics(std::string& out, const DaemonMetrics& m) {
  Family h(out, "spinewatch_pair_latency_seconds", "histogram",
           "Per-pair latency: the source handing the pair over to its posture being ready.");
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i < LatencyHistogram::kBounds.size(); ++i) {
    cumulative += m.latency.buckets[i];
    h.sample(static_cast<double>(cumulative), fmt::format("le=\"{}\"", LatencyHistogram::kBounds[i]), "_bucket");
  }
  cumulative += m.latency.buckets.back();
  h.sample(static_cast<double>(cumulative), "le=\"+Inf\"", "_bucket");
  h.sample(m.latency.sum_s, {}, "_sum");
  h.sample(static_cast<double>(m.latency.count), {}, "_count");
}

// The posture stream's clients and lines, and every bounded queue.
void stream_metrics(std::string& out, const DaemonMetrics& m) {
  const auto& c = m.publisher;
  const auto& p = m.pipeline;
  Family(out, "spinewatch_stream_clients", "gauge", "Posture stream clients connected (TCP and Unix socket).")
      .sample(c.clients);
  Family(out, "spinewatch_stream_clients_total", "counter", "Posture stream clients accepted.").sample(c.clients_total);
  Family(out, "spinewatch_stream_clients_dropped_total", "counter", "Posture stream clients dropped, by reason.")
      .sample(c.clients_dropped, "reason=\"slow_or_flooding\"")
      .sample(c.clients_rejected, "reason=\"max_clients\"");
  Family(out, "spinewatch_stream_refused_total", "counter",
         "Posture stream TCP clients refused before any line, by reason (docs/security.md).")
      .sample(c.auth_failures, "reason=\"auth\"")
      .sample(c.tls_failures, "reason=\"tls_handshake\"");
  Family(out, "spinewatch_stream_lines_total", "counter", "Lines published on the posture stream.").sample(c.lines);
  Family(out, "spinewatch_stream_lines_dropped_total", "counter", "Lines dropped before any client, by reason.")
      .sample(c.lines_dropped, "reason=\"inbox_full\"");

  Family(out, "spinewatch_queue_depth", "gauge", "Items waiting in each bounded queue now.")
      .sample(static_cast<std::uint64_t>(p.pair_queue), "queue=\"pairs\"")
      .sample(static_cast<std::uint64_t>(c.inbox), "queue=\"stream_inbox\"")
      .sample(static_cast<std::uint64_t>(m.live.mailbox), "queue=\"live_view\"");
  Family(out, "spinewatch_queue_capacity", "gauge", "Capacity of each bounded queue.")
      .sample(static_cast<std::uint64_t>(p.pair_queue_capacity), "queue=\"pairs\"")
      .sample(static_cast<std::uint64_t>(c.inbox_capacity), "queue=\"stream_inbox\"")
      .sample(static_cast<std::uint64_t>(m.live.mailbox_capacity), "queue=\"live_view\"");
}

// The HTTP server and the live view it serves.
void http_metrics(std::string& out, const DaemonMetrics& m) {
  const auto& h = m.http;
  Family(out, "spinewatch_http_connections", "gauge", "HTTP connections open.").sample(h.connections);
  Family(out, "spinewatch_http_connections_total", "counter", "HTTP connections accepted.").sample(h.connections_total);
  Family(out, "spinewatch_http_connections_dropped_total", "counter", "HTTP connections refused or cut, by reason.")
      .sample(h.rejected, "reason=\"max_connections\"")
      .sample(h.timed_out, "reason=\"timeout\"")
      .sample(h.bad_requests, "reason=\"bad_request\"")
      .sample(h.tls_failures, "reason=\"tls_handshake\"");
  Family(out, "spinewatch_http_unauthorized_total", "counter", "HTTP requests answered 401: no or a wrong bearer token.")
      .sample(h.auth_failures);
  Family(out, "spinewatch_http_requests_total", "counter", "HTTP requests answered.").sample(h.requests);
  Family(out, "spinewatch_http_stream_viewers", "gauge", "MJPEG /stream viewers connected.").sample(h.stream_viewers);
  Family(out, "spinewatch_http_stream_frames_total", "counter", "JPEG frames written to /stream viewers.")
      .sample(h.stream_frames);
  Family(out, "spinewatch_http_stream_frames_skipped_total", "counter",
         "Frames a /stream viewer did not get because it was still receiving an earlier one.")
      .sample(h.stream_frames_skipped, "reason=\"viewer_behind\"");

  const auto& l = m.live;
  Family(out, "spinewatch_live_samples_total", "counter", "Samples the estimator thread handed to the live view.")
      .sample(l.samples);
  Family(out, "spinewatch_live_samples_dropped_total", "counter", "Live view samples dropped, by reason.")
      .sample(l.samples_dropped, "reason=\"mailbox_full\"");
  Family(out, "spinewatch_live_frames_total", "counter", "Live view pictures drawn and JPEG-encoded.").sample(l.frames);
  Family(out, "spinewatch_live_render_seconds_total", "counter", "Time spent drawing and encoding live view pictures.")
      .sample(static_cast<double>(l.render_us) * 1e-6);
}

}  // namespace

std::string metrics_text(const DaemonMetrics& m) {
  std::string out;
  out.reserve(6000);
  pipeline_metrics(out, m);
  latency_metrics(out, m);
  stream_metrics(out, m);
  http_metrics(out, m);
  if (m.mqtt) mqtt_metrics(out, *m.mqtt);

  Family(out, "spinewatch_pairs_per_second", "gauge", "Pairs processed per second over the last second.")
      .sample(m.pairs_per_s);
  Family(out, "spinewatch_uptime_seconds", "gauge", "Seconds since the daemon started.").sample(m.uptime_s);
  return out;
}

}  // namespace spinewatch
