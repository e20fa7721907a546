#include "mqtt/mqtt_publisher.hpp"

#include <mosquitto.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "mqtt/mqtt_outbox.hpp"
#include "support/bounded_queue.hpp"

namespace spinewatch {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// QoS 1 messages out at once (summaries and alerts; postures apart): the
// rest wait in the outbox, not in libmosquitto's memory.
constexpr std::size_t kMaxInflight = 32;
constexpr std::size_t kMaxPostureInflight = 16;

struct Handoff {
  MqttTopic topic;  // Summary or Alert
  std::string line;
};

enum class Failure { Auth, Tls, Network };

struct Destroy {
  void operator()(mosquitto* m) const { mosquitto_destroy(m); }
};

}  // namespace

struct MqttPublisher::Impl {
  explicit Impl(MqttOptions options)
      : o(std::move(options)), postures(o.posture_queue), handoff(o.handoff_queue) {}

  MqttOptions o;
  std::string prefix;  // "spinewatch/<station>/"
  std::string client_id;
  std::unique_ptr<MqttOutbox> outbox;
  BoundedQueue<std::string> postures;
  BoundedQueue<Handoff> handoff;
  std::thread thread;
  std::atomic<bool> stopping{false};
  std::chrono::milliseconds grace{1000};
  std::once_flag stopped;

  // Estimator thread only: the next posture due.
  bool posture_started = false;
  std::int64_t next_posture_ns = 0;
  std::int64_t posture_period_ns = 0;

  // Counters (any thread reads, relaxed).
  std::atomic<bool> connected{false};
  std::atomic<std::uint64_t> outbox_messages{0}, dropped_disconnected{0}, dropped_queue_full{0}, dropped_outbox_full{0},
      dropped_handoff_full{0}, dropped_outbox_error{0}, reconnects{0}, failed_auth{0}, failed_tls{0}, failed_network{0},
      published_status{0}, published_summary{0}, published_alert{0}, published_posture{0};

  // The MQTT thread's own state.
  enum class State { Down, Connecting, Connected } state = State::Down;
  std::unique_ptr<mosquitto, Destroy> mosq;
  Clock::time_point attempt_started{}, next_attempt{};
  int failures = 0;  // in a row, since the link was last up
  bool outage = false;
  Clock::time_point outage_since{};
  std::optional<std::pair<Failure, std::string>> pending_failure;  // set by callbacks and errors
  std::string last_error_log;  // libmosquitto's last error message (TLS verification, …)
  std::map<int, std::pair<std::int64_t, MqttTopic>> inflight;  // mid → outbox id, topic
  std::set<int> posture_inflight;
  std::int64_t cursor = 0;    // the last outbox id published on this link
  bool outbox_dirty = true;   // something may be in the outbox past the cursor
  std::optional<int> status_mid;
  bool status_acked = false;

  std::string topic(MqttTopic t) const { return prefix + std::string(topic_leaf(t)); }
  std::string where() const { return fmt::format("{}://{}:{}", o.url.tls ? "mqtts" : "mqtt", o.url.host, o.url.port); }

  // ---- the MQTT thread ----

  void run() {
    while (!stopping.load()) {
      drain_handoff(mosq ? 0ms : 20ms);  // waiting for a handover is the idle sleep while there is no link
      if (!mosq) {
        if (Clock::now() >= next_attempt) begin_connect();
        continue;
      }
      step(10);
    }
    shutdown();
  }

  // One turn of libmosquitto's loop, then what the link can take.
  void step(int timeout_ms) {
    const int rc = mosquitto_loop(mosq.get(), timeout_ms, 1);
    if (!pending_failure && rc != MOSQ_ERR_SUCCESS) pending_failure = classify(rc);
    if (!pending_failure && state == State::Connecting &&
        Clock::now() - attempt_started > std::chrono::seconds(std::max(5, o.keepalive_s)))
      pending_failure = {Failure::Network, "no CONNACK from the broker in time"};
    if (pending_failure) return fail();
    if (state == State::Connected) {
      send_outbox();
      send_postures();
    }
  }

  std::pair<Failure, std::string> classify(int rc) const {
    std::string why = rc == MOSQ_ERR_ERRNO ? std::string(std::strerror(errno)) : mosquitto_strerror(rc);
    if (!last_error_log.empty()) why += " (" + last_error_log + ")";
    const bool tls = rc == MOSQ_ERR_TLS || rc == MOSQ_ERR_TLS_HANDSHAKE || last_error_log.find("SSL") != std::string::npos ||
                     last_error_log.find("certificate") != std::string::npos;
    return {tls ? Failure::Tls : Failure::Network, why};
  }

  void drain_handoff(std::chrono::milliseconds wait) {
    for (auto item = handoff.pop_for(wait); item; item = handoff.pop_for(0ms)) {
      auto dropped = outbox->append(item->topic, item->line);
      if (!dropped) {
        dropped_outbox_error.fetch_add(1, std::memory_order_relaxed);
        spdlog::error("{}; the {} is lost", dropped.error().message, topic_leaf(item->topic));
        continue;
      }
      if (*dropped) {
        if (dropped_outbox_full.load() == 0)
          spdlog::warn("mqtt outbox {}: full ({} messages, mqtt.outbox_max_messages): dropping the oldest (counted)",
                       o.outbox_path.string(), o.outbox_max_messages);
        dropped_outbox_full.fetch_add(*dropped, std::memory_order_relaxed);
      }
      outbox_dirty = true;
      outbox_messages.store(outbox->size(), std::memory_order_relaxed);
    }
  }

  void begin_connect() {
    last_error_log.clear();
    pending_failure.reset();
    attempt_started = Clock::now();
    mosq.reset(mosquitto_new(client_id.c_str(), true, this));
    if (!mosq) return fail_now(Failure::Network, "out of memory");
    mosquitto_connect_callback_set(mosq.get(), [](mosquitto*, void* self, int rc) { static_cast<Impl*>(self)->on_connect(rc); });
    mosquitto_disconnect_callback_set(mosq.get(), [](mosquitto*, void* self, int rc) { static_cast<Impl*>(self)->on_disconnect(rc); });
    mosquitto_publish_callback_set(mosq.get(), [](mosquitto*, void* self, int mid) { static_cast<Impl*>(self)->on_publish(mid); });
    mosquitto_log_callback_set(mosq.get(), [](mosquitto*, void* self, int level, const char* text) {
      if (level == MOSQ_LOG_ERR && text) static_cast<Impl*>(self)->last_error_log = text;
    });
    const std::string status = topic(MqttTopic::Status);
    if (int rc = mosquitto_will_set(mosq.get(), status.c_str(), 7, "offline", 1, true); rc != MOSQ_ERR_SUCCESS)
      return fail_now(Failure::Network, std::string("last will: ") + mosquitto_strerror(rc));
    if (!o.username.empty())
      if (int rc = mosquitto_username_pw_set(mosq.get(), o.username.c_str(), o.password ? o.password->c_str() : nullptr);
          rc != MOSQ_ERR_SUCCESS)
        return fail_now(Failure::Auth, std::string("credentials: ") + mosquitto_strerror(rc));
    if (o.url.tls) {
      const char* ca = o.ca_file.empty() ? nullptr : o.ca_file.c_str();
      if (int rc = mosquitto_tls_set(mosq.get(), ca, ca ? nullptr : "/etc/ssl/certs",
                                     o.cert_file.empty() ? nullptr : o.cert_file.c_str(),
                                     o.key_file.empty() ? nullptr : o.key_file.c_str(), nullptr);
          rc != MOSQ_ERR_SUCCESS)
        return fail_now(Failure::Tls, fmt::format("TLS set-up (ca_file, cert_file, key_file): {}{}", mosquitto_strerror(rc),
                                                  last_error_log.empty() ? "" : " (" + last_error_log + ")"));
    }
    state = State::Connecting;
    // Asynchronous: a broker that does not answer costs this thread no wait
    // (a host name is still resolved here, as libmosquitto does).
    if (int rc = mosquitto_connect_async(mosq.get(), o.url.host.c_str(), o.url.port, o.keepalive_s); rc != MOSQ_ERR_SUCCESS) {
      auto f = classify(rc);
      return fail_now(f.first, f.second);
    }
  }

  void fail_now(Failure f, std::string why) {
    pending_failure = {f, std::move(why)};
    fail();
  }

  void on_connect(int rc) {
    if (rc != 0) {
      pending_failure = {Failure::Auth, fmt::format("the broker refused the connection: {}", mosquitto_connack_string(rc))};
      return;
    }
    state = State::Connected;
    connected.store(true);
    if (outage) {
      reconnects.fetch_add(1, std::memory_order_relaxed);
      spdlog::info("mqtt: connected to {} again after {:.1f} s ({} failed attempts); {} messages in the outbox to send",
                   where(), std::chrono::duration<double>(Clock::now() - outage_since).count(), failures,
                   outbox->size());
      outage = false;
    } else {
      spdlog::info("mqtt: connected to {} as {}; publishing under {}", where(), client_id, prefix);
    }
    failures = 0;
    int mid = 0;
    if (mosquitto_publish(mosq.get(), &mid, topic(MqttTopic::Status).c_str(), 6, "online", 1, true) == MOSQ_ERR_SUCCESS)
      status_mid = mid;
    outbox_dirty = true;
    cursor = 0;
  }

  void on_disconnect(int rc) {
    if (stopping.load() && rc == 0) return;  // ours
    if (!pending_failure)
      pending_failure = {Failure::Network,
                         rc == 0 ? "disconnected" : fmt::format("connection lost: {}", mosquitto_strerror(rc))};
  }

  void on_publish(int mid) {
    if (auto it = inflight.find(mid); it != inflight.end()) {
      if (auto s = outbox->remove(it->second.first); !s) spdlog::error("{}", s.error().message);
      (it->second.second == MqttTopic::Alert ? published_alert : published_summary).fetch_add(1, std::memory_order_relaxed);
      outbox_messages.store(outbox->size(), std::memory_order_relaxed);
      inflight.erase(it);
    } else if (posture_inflight.erase(mid)) {
      published_posture.fetch_add(1, std::memory_order_relaxed);
    } else if (status_mid && *status_mid == mid) {
      published_status.fetch_add(1, std::memory_order_relaxed);
      status_acked = true;
    }  // else: a QoS 0 posture (counted when written), or one of a link since lost
  }

  // The link is gone (or never came): everything in flight is sent again
  // from the outbox on the next link; postures are dropped; back off.
  void fail() {
    auto [failure, why] = pending_failure.value_or(std::pair{Failure::Network, std::string("unknown")});
    pending_failure.reset();
    const bool was_connected = state == State::Connected;
    mosq.reset();
    state = State::Down;
    connected.store(false);
    inflight.clear();
    posture_inflight.clear();
    status_mid.reset();
    cursor = 0;
    outbox_dirty = true;
    std::uint64_t stale = 0;
    while (postures.pop_for(0ms)) ++stale;
    dropped_disconnected.fetch_add(stale, std::memory_order_relaxed);
    if (was_connected) {
      failures = 1;
    } else {
      ++failures;
      (failure == Failure::Auth ? failed_auth : failure == Failure::Tls ? failed_tls : failed_network)
          .fetch_add(1, std::memory_order_relaxed);
    }
    const auto delay = mqtt_reconnect_delay(failures, o.reconnect_min_s, o.reconnect_max_s);
    next_attempt = Clock::now() + delay;
    if (!outage) {
      outage = true;
      outage_since = Clock::now();
      spdlog::warn("mqtt: {}: {}; retrying in {:.1f} s, backing off up to {:.1f} s (logged once per outage); "
                   "summaries and alerts are kept in the outbox {} ({} now), postures are dropped meanwhile",
                   where(), why, delay.count() / 1000.0, o.reconnect_max_s, o.outbox_path.string(), outbox->size());
    } else {
      spdlog::debug("mqtt: {}: {}; retrying in {:.1f} s", where(), why, delay.count() / 1000.0);
    }
  }

  void send_outbox() {
    while (outbox_dirty && inflight.size() < kMaxInflight) {
      const std::size_t room = kMaxInflight - inflight.size();
      auto messages = outbox->after(cursor, room);
      if (!messages) {
        spdlog::error("{}", messages.error().message);
        return;
      }
      if (messages->size() < room) outbox_dirty = false;
      if (messages->empty()) return;
      for (const auto& m : *messages) {
        int mid = 0;
        const int rc = mosquitto_publish(mosq.get(), &mid, topic(m.topic).c_str(), static_cast<int>(m.payload.size()),
                                         m.payload.data(), 1, false);
        if (rc != MOSQ_ERR_SUCCESS) {
          outbox_dirty = true;
          if (!pending_failure) pending_failure = classify(rc);
          return;
        }
        inflight[mid] = {m.id, m.topic};
        cursor = m.id;
      }
    }
  }

  // Postures only while the connection has room: what libmosquitto cannot
  // write now waits in the bounded queue, where overflow is counted.
  void send_postures() {
    while (!mosquitto_want_write(mosq.get()) && posture_inflight.size() < kMaxPostureInflight) {
      auto line = postures.pop_for(0ms);
      if (!line) return;
      int mid = 0;
      const std::string t = topic(MqttTopic::Posture);
      if (mosquitto_publish(mosq.get(), &mid, t.c_str(), static_cast<int>(line->size()), line->data(), o.qos, false) !=
          MOSQ_ERR_SUCCESS) {
        dropped_disconnected.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      if (o.qos == 1) posture_inflight.insert(mid);
      else published_posture.fetch_add(1, std::memory_order_relaxed);  // QoS 0: written to the connection
    }
  }

  // At stop: the outbox sent while the grace lasts, then "offline" said
  // (a clean disconnect sends no last will) and the link closed.
  void shutdown() {
    drain_handoff(0ms);
    if (mosq && state == State::Connected) {
      const auto deadline = Clock::now() + grace;
      while (state == State::Connected && outbox->size() > 0 && Clock::now() < deadline) step(10);
      if (state == State::Connected) {
        int mid = 0;
        status_acked = false;
        if (mosquitto_publish(mosq.get(), &mid, topic(MqttTopic::Status).c_str(), 7, "offline", 1, true) == MOSQ_ERR_SUCCESS) {
          status_mid = mid;
          const auto until = Clock::now() + std::max(grace, std::chrono::milliseconds(500));
          while (!status_acked && Clock::now() < until && mosquitto_loop(mosq.get(), 10, 1) == MOSQ_ERR_SUCCESS) {
          }
        }
        mosquitto_disconnect(mosq.get());
        mosquitto_loop(mosq.get(), 10, 1);
      }
    }
    mosq.reset();
    connected.store(false);
    if (outbox->size() > 0)
      spdlog::info("mqtt: {} messages left in the outbox {}, sent at the next start", outbox->size(),
                   o.outbox_path.string());
  }
};

MqttPublisher::MqttPublisher() = default;

Result<std::unique_ptr<MqttPublisher>> MqttPublisher::start(MqttOptions options) {
  static std::once_flag init;
  std::call_once(init, [] { mosquitto_lib_init(); });
  auto outbox = MqttOutbox::open(options.outbox_path, options.outbox_max_messages);
  if (!outbox) return Error{"mqtt.outbox_path: " + outbox.error().message};
  std::unique_ptr<MqttPublisher> p(new MqttPublisher());
  p->impl_ = std::make_unique<Impl>(std::move(options));
  Impl& d = *p->impl_;
  const std::string station = topic_safe_station(d.o.station);
  d.prefix = "spinewatch/" + station + "/";
  d.client_id = "spinewatch-" + station;
  d.outbox = std::move(outbox).value();
  d.outbox_messages = d.outbox->size();
  if (d.o.posture_rate_hz > 0) d.posture_period_ns = static_cast<std::int64_t>(1e9 / d.o.posture_rate_hz);
  if (d.outbox->size() > 0)
    spdlog::info("mqtt: {} messages waiting in the outbox {} from before", d.outbox->size(), d.o.outbox_path.string());
  d.thread = std::thread([&d] { d.run(); });
  return p;
}

MqttPublisher::~MqttPublisher() { stop(); }

void MqttPublisher::stop(std::chrono::milliseconds grace) {
  if (!impl_) return;
  std::call_once(impl_->stopped, [&] {
    impl_->grace = grace;
    impl_->stopping.store(true);
    if (impl_->thread.joinable()) impl_->thread.join();
  });
}

void MqttPublisher::offer_posture(std::int64_t t_ns, const std::string& line) {
  Impl& d = *impl_;
  if (d.posture_period_ns == 0) return;
  // A few milliseconds early still counts: camera timestamps jitter, and
  // 5 Hz of a 30 Hz stream should be every sixth posture, not every seventh.
  const std::int64_t slack = std::min<std::int64_t>(d.posture_period_ns / 4, 5'000'000);
  if (d.posture_started && t_ns < d.next_posture_ns - slack) return;
  // Due: the next one a period on, or a period from now after a gap.
  d.next_posture_ns = d.posture_started && t_ns - d.next_posture_ns < d.posture_period_ns ? d.next_posture_ns + d.posture_period_ns
                                                                                         : t_ns + d.posture_period_ns;
  d.posture_started = true;
  if (!d.connected.load(std::memory_order_relaxed)) {
    d.dropped_disconnected.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (d.postures.push(line)) d.dropped_queue_full.fetch_add(1, std::memory_order_relaxed);
}

void MqttPublisher::publish_summary(std::string line) {
  if (impl_->handoff.push({MqttTopic::Summary, std::move(line)}))
    impl_->dropped_handoff_full.fetch_add(1, std::memory_order_relaxed);
}

void MqttPublisher::publish_alert(std::string line) {
  if (impl_->handoff.push({MqttTopic::Alert, std::move(line)}))
    impl_->dropped_handoff_full.fetch_add(1, std::memory_order_relaxed);
}

std::string MqttPublisher::topic(MqttTopic topic) const { return impl_->topic(topic); }

const std::string& MqttPublisher::prefix() const { return impl_->prefix; }

MqttStats MqttPublisher::stats() const {
  const Impl& d = *impl_;
  constexpr auto r = std::memory_order_relaxed;
  MqttStats s;
  s.connected = d.connected.load(r);
  s.outbox_messages = d.outbox_messages.load(r);
  s.dropped_disconnected = d.dropped_disconnected.load(r);
  s.dropped_queue_full = d.dropped_queue_full.load(r);
  s.dropped_outbox_full = d.dropped_outbox_full.load(r);
  s.dropped_handoff_full = d.dropped_handoff_full.load(r);
  s.dropped_outbox_error = d.dropped_outbox_error.load(r);
  s.reconnects = d.reconnects.load(r);
  s.failed_auth = d.failed_auth.load(r);
  s.failed_tls = d.failed_tls.load(r);
  s.failed_network = d.failed_network.load(r);
  s.published_status = d.published_status.load(r);
  s.published_summary = d.published_summary.load(r);
  s.published_alert = d.published_alert.load(r);
  s.published_posture = d.published_posture.load(r);
  return s;
}

}  // namespace spinewatch
