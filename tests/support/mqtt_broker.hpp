#pragma once
// A real MQTT broker for tests: Debian's /usr/sbin/mosquitto on loopback at
// a free port, with a generated configuration, stopped (SIGTERM) when the
// object goes; and a subscriber (libmosquitto, its own network thread) that
// records every message on spinewatch/#.
#include <fcntl.h>
#include <mosquitto.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

extern char** environ;

namespace spinewatch::test {

inline constexpr const char* kMosquitto = "/usr/sbin/mosquitto";

inline bool mosquitto_available() { return ::access(kMosquitto, X_OK) == 0; }

inline bool port_accepts(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  ::close(fd);
  return ok;
}

class MosquittoBroker {
 public:
  // `listeners`: the configuration's listener blocks ("listener PORT 127.0.0.1\n…"),
  // with per_listener_settings on; `ports`: the ports to wait for.
  MosquittoBroker(std::filesystem::path dir, std::string listeners, std::vector<std::uint16_t> ports)
      : dir_(std::move(dir)), ports_(std::move(ports)) {
    std::filesystem::create_directories(dir_);
    std::string conf = "per_listener_settings true\npersistence true\npersistence_location " + dir_.string() +
                       "/\nlog_dest file " + (dir_ / "mosquitto.log").string() + "\nlog_type all\n";
    if (::geteuid() == 0) conf += "user root\n";  // else mosquitto drops to user mosquitto, who cannot write here
    write_file(dir_ / "mosquitto.conf", conf + listeners);
  }
  ~MosquittoBroker() { stop(); }

  // Starts it and waits until every port accepts; false (with the log) if not.
  bool start() {
    const std::string conf = (dir_ / "mosquitto.conf").string();
    const std::string out = (dir_ / "mosquitto.out").string();
    std::vector<char*> argv{const_cast<char*>(kMosquitto), const_cast<char*>("-c"), const_cast<char*>(conf.c_str()), nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    const int rc = posix_spawn(&pid_, kMosquitto, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      pid_ = -1;
      return false;
    }
    const auto deadline = std::chrono::steady_clock::now() + scaled(std::chrono::seconds(10));
    for (std::uint16_t port : ports_)
      while (!port_accepts(port)) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    return true;
  }
  // SIGTERM (it saves its persistence database) and wait.
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  std::string log() const { return read_file(dir_ / "mosquitto.log") + read_file(dir_ / "mosquitto.out"); }

 private:
  std::filesystem::path dir_;
  std::vector<std::uint16_t> ports_;
  pid_t pid_ = -1;
};

struct MqttMessage {
  std::string topic, payload;
  int qos = 0;
  bool retain = false;
};

struct SubscriberOptions {
  std::uint16_t port = 0;
  std::string client_id = "spinewatch-test-subscriber";
  bool clean_session = true;  // false: the broker queues QoS 1 messages while it is away
  std::string username = "", password = "";
  std::string ca_file = "";  // TLS when set
};

class MqttSubscriber {
 public:
  explicit MqttSubscriber(const SubscriberOptions& o) {
    mosquitto_lib_init();
    mosq_ = mosquitto_new(o.client_id.c_str(), o.clean_session, this);
    if (!o.username.empty()) mosquitto_username_pw_set(mosq_, o.username.c_str(), o.password.c_str());
    if (!o.ca_file.empty()) mosquitto_tls_set(mosq_, o.ca_file.c_str(), nullptr, nullptr, nullptr, nullptr);
    mosquitto_reconnect_delay_set(mosq_, 1, 1, false);
    mosquitto_connect_callback_set(mosq_, [](mosquitto* m, void* self, int rc) {
      if (rc == 0) mosquitto_subscribe(m, nullptr, "spinewatch/#", 1);
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard lock(s->mutex_);
      s->connects_ += rc == 0;
      s->changed_.notify_all();
    });
    mosquitto_subscribe_callback_set(mosq_, [](mosquitto*, void* self, int, int, const int*) {
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard lock(s->mutex_);
      ++s->subscribed_;
      s->changed_.notify_all();
    });
    mosquitto_message_callback_set(mosq_, [](mosquitto*, void* self, const mosquitto_message* m) {
      auto* s = static_cast<MqttSubscriber*>(self);
      std::lock_guard lock(s->mutex_);
      s->messages_.push_back({m->topic, std::string(static_cast<const char*>(m->payload), static_cast<std::size_t>(m->payloadlen)),
                              m->qos, m->retain});
      s->changed_.notify_all();
    });
    mosquitto_connect_async(mosq_, "127.0.0.1", o.port, 10);
    mosquitto_loop_start(mosq_);
  }
  // The loop thread is stopped, not cancelled: a cancel lands at the first
  // cancellation point, which may be the PUBACK's write while a received
  // message is still allocated, and LeakSanitizer then fails the test.
  // After the disconnect the thread leaves its loop by itself (and a
  // reconnect wait is woken by loop_stop), so the join returns.
  ~MqttSubscriber() {
    mosquitto_disconnect(mosq_);
    mosquitto_loop_stop(mosq_, false);
    mosquitto_destroy(mosq_);
  }
  MqttSubscriber(const MqttSubscriber&) = delete;
  MqttSubscriber& operator=(const MqttSubscriber&) = delete;

  // Waits until `done(messages)` holds; whether it did within the timeout.
  bool wait_for(std::chrono::milliseconds timeout, const std::function<bool(const std::vector<MqttMessage>&)>& done) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return done(messages_); });
  }
  bool wait_subscribed(std::chrono::milliseconds timeout, int times = 1) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return subscribed_ >= times; });
  }
  std::vector<MqttMessage> messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
  }
  std::vector<MqttMessage> on(const std::string& topic) const {
    std::vector<MqttMessage> out;
    for (auto& m : messages())
      if (m.topic == topic) out.push_back(m);
    return out;
  }

 private:
  mosquitto* mosq_ = nullptr;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<MqttMessage> messages_;
  int connects_ = 0, subscribed_ = 0;
};

// The last message on `topic`, if any.
inline std::optional<MqttMessage> last_on(const std::vector<MqttMessage>& messages, const std::string& topic) {
  for (auto it = messages.rbegin(); it != messages.rend(); ++it)
    if (it->topic == topic) return *it;
  return std::nullopt;
}

}  // namespace spinewatch::test
