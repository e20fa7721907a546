#pragma once
// The HTTP server's shared state (private to daemon/src/http): the
// listener, the open sessions and the latest live view sample, all used on
// the I/O thread only, and the counters, read from anywhere.
#include <atomic>
#include <memory>
#include <optional>
#include <set>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

#include <spdlog/spdlog.h>

#include "http/http_server.hpp"

namespace spinewatch {

namespace http_detail {
// One connection, plain or TLS (http_session.hpp), as the server sees it.
class SessionBase {
 public:
  virtual ~SessionBase() = default;
  virtual void start() = 0;
  virtual void close() = 0;
  virtual void on_frame(const std::shared_ptr<const LiveFrame>& frame) = 0;
};
}

struct HttpServer::Impl : std::enable_shared_from_this<HttpServer::Impl> {
  Impl(boost::asio::io_context& io_context, HttpOptions o, HttpHandlers h, StationInfo s, LiveView& l)
      : io(io_context), options(std::move(o)), handlers(std::move(h)), station(std::move(s)), live(l) {}

  boost::asio::io_context& io;
  const HttpOptions options;
  const HttpHandlers handlers;
  const StationInfo station;
  LiveView& live;
  std::optional<boost::asio::ip::tcp::acceptor> acceptor;
  std::uint16_t port = 0;
  // I/O thread only:
  std::set<std::shared_ptr<http_detail::SessionBase>> sessions;
  std::shared_ptr<const LiveFrame> latest, latest_picture;
  bool stopped = false;

  std::atomic<std::uint64_t> connections{0}, connections_total{0}, rejected{0}, timed_out{0}, bad_requests{0},
      requests{0}, stream_viewers{0}, stream_frames{0}, stream_frames_skipped{0}, auth_failures{0}, tls_failures{0};
  LogLimiter refusal_log;  // I/O thread only

  // A refused client, logged at most once per 10 s (never the token).
  void refused(const std::string& peer, std::string_view why) {
    if (auto held = refusal_log.admit())
      spdlog::warn("http: {} refused: {}{}", peer, why,
                   *held ? " (" + std::to_string(*held) + " more refusals not logged in the last 10 s)" : std::string());
  }

  void accept_next();
  void admit(boost::asio::ip::tcp::socket socket);
  void forget(const std::shared_ptr<http_detail::SessionBase>& session);
  void deliver(std::shared_ptr<const LiveFrame> frame);

  HttpStats stats() const {
    HttpStats s;
    s.connections = connections.load();
    s.connections_total = connections_total.load();
    s.rejected = rejected.load();
    s.timed_out = timed_out.load();
    s.bad_requests = bad_requests.load();
    s.requests = requests.load();
    s.stream_viewers = stream_viewers.load();
    s.stream_frames = stream_frames.load();
    s.stream_frames_skipped = stream_frames_skipped.load();
    s.auth_failures = auth_failures.load();
    s.tls_failures = tls_failures.load();
    return s;
  }
  DaemonMetrics metrics() const {
    DaemonMetrics m = handlers.metrics ? handlers.metrics() : DaemonMetrics{};
    m.http = stats();
    m.live = live.stats();
    return m;
  }
};

}  // namespace spinewatch
