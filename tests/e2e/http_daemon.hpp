#pragma once
// The real spinewatchd on its embedded default (the bundled phantom
// recording, looped at its recorded rate) with the HTTP live view on, for
// the live view's end-to-end and browser tests.
#include <chrono>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "http_client.hpp"
#include "daemon_process.hpp"
#include "test_support.hpp"

namespace spinewatch::test {

class HttpDaemon {
 public:
  // `http_keys`: lines of the [http] section (listen comes from --http).
  HttpDaemon(const TempDir& dir, const std::string& http_keys)
      : stream_port_(free_port()), http_port_(free_port()) {
    const auto config = dir / "spinewatch.toml";
    write_file(config, "[station]\nname = \"live\"\n[cameras]\nsource = \"recording\"\nrecording = \"\"\n"
                       "frontal = \"/nonexistent/video0\"\nlateral = \"/nonexistent/video2\"\n"
                       "calibration = \"/nonexistent/cal.yaml\"\n[publish]\nclient_queue = 100000\n[http]\n" +
                           http_keys);
    daemon_.emplace(std::vector<std::string>{test::daemon_path(), "--config", config.string(), "--listen",
                                             "127.0.0.1:" + std::to_string(stream_port_), "--unix", "none", "--http",
                                             "127.0.0.1:" + std::to_string(http_port_)},
                    dir / "daemon.log");
  }
  // The daemon as scripts/demo (`make demo`) starts it: config/demo.toml,
  // the posture stream on TCP, the live view on loopback (no Unix socket
  // here: the demo's is in its build directory).
  struct AsTheDemo {};
  HttpDaemon(const TempDir& dir, AsTheDemo) : stream_port_(free_port()), http_port_(free_port()) {
    daemon_.emplace(std::vector<std::string>{test::daemon_path(), "--config", test::source_dir() + "/config/demo.toml",
                                             "--listen", "127.0.0.1:" + std::to_string(stream_port_), "--unix", "none",
                                             "--http", "127.0.0.1:" + std::to_string(http_port_)},
                    dir / "daemon.log");
  }
  ~HttpDaemon() {
    if (daemon_ && daemon_->running()) {
      daemon_->signal(SIGTERM);
      daemon_->wait_exit(scaled(std::chrono::milliseconds(3000)));
    }
  }
  DaemonProcess& process() { return *daemon_; }
  std::uint16_t http_port() const { return http_port_; }
  std::uint16_t stream_port() const { return stream_port_; }

  // Waits until /state answers with `state` (e.g. "tracking").
  bool wait_for_state(const std::string& state, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline && daemon_->running()) {
      const auto r = http_get(http_port_, "/state", std::chrono::seconds(3));
      if (r.status == 200 && nlohmann::json::parse(r.body).at("state") == state) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

 private:
  std::uint16_t stream_port_, http_port_;
  std::optional<DaemonProcess> daemon_;
};

}  // namespace spinewatch::test
