#pragma once
// The daemon's HTTP server (docs/interfaces.md §5; docs/daemon.md, "Live view"):
// the live view page, /stream (MJPEG), /snapshot, /state, /metrics and
// POST /background/relearn, with Boost.Beast on an existing io_context
// (the daemon's network loop, net/network_loop.hpp), never on the
// estimator thread.
//
// Nothing a client does can stall the daemon: a connection limit (further
// ones are answered 503 and closed at once), a header size limit (431 and
// closed), a deadline for each request to arrive and for each response or
// stream frame to be taken (else the connection is cut), one frame in
// flight per /stream viewer plus the newest waiting (older ones are
// skipped, counted). Every refusal and cut is counted (HttpStats).
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "access/access.hpp"
#include "http/daemon_metrics.hpp"
#include "http/live_view.hpp"
#include "http/state_json.hpp"
#include "spinewatch/daemon/endpoint.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct HttpOptions {
  TcpEndpoint endpoint{};
  std::size_t max_connections = 16;
  std::chrono::milliseconds timeout{10000};  // request arrival; each response / stream frame written
  std::size_t max_header_bytes = 8192;
  int stream_send_buffer = 64 * 1024;  // SO_SNDBUF of /stream connections: bounds what a viewer holds
  // TLS (the handshake within `timeout`) and who may ask: with tokens,
  // every request needs Authorization: Bearer (docs/security.md).
  Access access{};
};

// What the server asks the daemon for, on the I/O thread (must not block).
struct HttpHandlers {
  std::function<DaemonMetrics()> metrics;        // counters without HttpStats (the server adds its own)
  std::function<bool()> relearn_background;      // true: the estimator will re-learn before its next pair
};

class HttpServer {
 public:
  // Binds (errors name the address) and starts accepting on `io`. `live`
  // must outlive the server; its frames reach the server via on_frame().
  static Result<std::unique_ptr<HttpServer>> start(boost::asio::io_context& io, HttpOptions options,
                                                   HttpHandlers handlers, StationInfo station, LiveView& live);
  ~HttpServer();  // stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // From any thread (the live view's): a new sample, with or without a picture.
  void on_frame(std::shared_ptr<const LiveFrame> frame);
  // From a thread other than the I/O thread: closes the listener and every
  // connection and, while the loop runs, waits (up to a second) until
  // their handlers are done. Idempotent.
  void stop();

  std::uint16_t port() const;
  HttpStats stats() const;

  struct Impl;

 private:
  explicit HttpServer(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
  bool stop_called_ = false;
};

}  // namespace spinewatch
