#pragma once
// Publishes the station to the site's MQTT broker (docs/interfaces.md §7,
// docs/fleet.md) on a thread of its own, with libmosquitto:
//   spinewatch/<station>/status   retained "online"; "offline" as the last will
//   spinewatch/<station>/summary  summary lines, QoS 1, through the outbox
//   spinewatch/<station>/alert    alert lines, QoS 1, through the outbox
//   spinewatch/<station>/posture  posture lines, at most posture_rate_hz, QoS as configured
// The estimator thread only hands lines over (bounded queues, never a wait):
// summaries and alerts go to the persistent outbox (MqttOutbox) and leave it
// when the broker acknowledges them; postures are dropped, and counted,
// while the link is down or their queue is full. A lost link is retried
// with a doubling back-off, logged once per outage, counted.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "spinewatch/daemon/config.hpp"
#include "mqtt/mqtt_topic.hpp"
#include "spinewatch/frames/result.hpp"
#include "support/mqtt_url.hpp"

namespace spinewatch {

struct MqttOptions {
  MqttUrl url;
  std::string station;  // as configured; the topics use topic_safe_station(station)
  std::string ca_file, cert_file, key_file;
  std::string username;
  std::optional<std::string> password;  // read from password_file at start
  double posture_rate_hz = 1.0;         // 0: no posture messages
  int qos = 0;                          // of postures
  std::filesystem::path outbox_path;
  std::size_t outbox_max_messages = 100000;
  int keepalive_s = 30;
  double reconnect_min_s = 1.0, reconnect_max_s = 60.0;
  std::size_t posture_queue = 64;    // postures waiting for the thread
  std::size_t handoff_queue = 1024;  // summaries and alerts waiting to be written to the outbox
};

// [mqtt] → options, nothing when url is "". Reads password_file (refused
// when group or others may read it) and checks that the TLS files can be
// read, so that a mistake stops the daemon at start with the key named.
// An empty outbox_path is mqtt-outbox.db in the state directory:
// $STATE_DIRECTORY (systemd), else /var/lib/spinewatch when writable, else
// the user's $XDG_STATE_HOME/spinewatch or ~/.local/state/spinewatch.
Result<std::optional<MqttOptions>> mqtt_options(const Config& config);

struct MqttStats {
  bool connected = false;
  std::uint64_t outbox_messages = 0;  // waiting for the broker's acknowledgement now
  // Dropped messages by reason.
  std::uint64_t dropped_disconnected = 0;  // postures while the link was down
  std::uint64_t dropped_queue_full = 0;    // postures: the link could not take them as fast
  std::uint64_t dropped_outbox_full = 0;   // summaries/alerts: the oldest, outbox at outbox_max_messages
  std::uint64_t dropped_handoff_full = 0;  // summaries/alerts: the thread could not write them to the outbox in time
  std::uint64_t dropped_outbox_error = 0;  // summaries/alerts the outbox could not store (disk full, I/O error)
  std::uint64_t reconnects = 0;            // links made again after an outage
  // Connection attempts that failed, by reason.
  std::uint64_t failed_auth = 0;     // the broker refused the CONNECT (bad user name or password, not authorised)
  std::uint64_t failed_tls = 0;      // TLS handshake (certificate not trusted, wrong host name)
  std::uint64_t failed_network = 0;  // unreachable, refused, name not known, no answer
  // Messages the broker has (QoS 1: acknowledged; QoS 0: written to the connection), by topic.
  std::uint64_t published_status = 0, published_summary = 0, published_alert = 0, published_posture = 0;

  // Dropped for any reason (the posture lines' mqtt_dropped, the status line).
  std::uint64_t dropped() const {
    return dropped_disconnected + dropped_queue_full + dropped_outbox_full + dropped_handoff_full + dropped_outbox_error;
  }
};

class MqttPublisher {
 public:
  // Opens the outbox and starts the thread, which connects (and retries) on its own.
  static Result<std::unique_ptr<MqttPublisher>> start(MqttOptions options);
  ~MqttPublisher();  // stop()
  MqttPublisher(const MqttPublisher&) = delete;
  MqttPublisher& operator=(const MqttPublisher&) = delete;

  // Estimator thread (one caller): a posture line and its time; copied and
  // queued only when one is due at posture_rate_hz.
  void offer_posture(std::int64_t t_ns, const std::string& line);
  // Any thread: into the outbox, sent when the broker is there.
  void publish_summary(std::string line);
  void publish_alert(std::string line);

  // Writes what was handed over to the outbox, gives a connected link up to
  // `grace` to send it, publishes "offline" (retained), disconnects, joins.
  // Idempotent.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(1000));

  MqttStats stats() const;
  std::string topic(MqttTopic topic) const;  // "spinewatch/<station>/<leaf>"
  const std::string& prefix() const;        // "spinewatch/<station>/"

 private:
  MqttPublisher();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
