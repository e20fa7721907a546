#pragma once
// One HTTP connection of the live view (private to daemon/src/http), on
// the I/O thread only: reads requests one at a time (keep-alive) within
// the timeout, answers each, and for /stream becomes an MJPEG viewer with
// one frame in flight and the newest one waiting.
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "http/http_routes.hpp"
#include "http/http_server_impl.hpp"
#include "pipeline/pipeline.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch {

std::string_view live_view_page();  // embedded daemon/src/http/live_view.html

namespace http_detail {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

inline constexpr std::string_view kBoundary = "spinewatchframe";
// A picture this recent answers /snapshot at once; an older one waits for the next.
inline constexpr std::int64_t kFreshNs = 1'000'000'000;
// /state and /snapshot keep the live view sampling this long after each request.
inline constexpr std::int64_t kWantedNs = 5'000'000'000;
inline constexpr auto kStateWait = std::chrono::milliseconds(1500);
inline constexpr auto kSnapshotWait = std::chrono::milliseconds(3000);

using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// What a response carries. Its Content-Type follows from it, and a page a
// browser runs (Html) is sent with a Content-Security-Policy.
enum class Body : std::uint8_t { Html, Text, Metrics, Json, Jpeg };

constexpr std::string_view content_type(Body body) {
  switch (body) {
    case Body::Html: return "text/html; charset=utf-8";
    case Body::Text: return "text/plain";
    case Body::Metrics: return "text/plain; version=0.0.4; charset=utf-8";  // Prometheus' text format
    case Body::Json: return "application/json";
    case Body::Jpeg: return "image/jpeg";
  }
  return "application/octet-stream";
}

// Stream: beast::tcp_stream, or TlsStream when the server has a certificate.
template <class Stream>
class HttpSession final : public SessionBase, public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

  HttpSession(Stream stream, std::shared_ptr<HttpServer::Impl> server)
      : stream_(std::move(stream)), server_(std::move(server)), buffer_(server_->options.max_header_bytes),
        wait_timer_(server_->io) {}

  void start() override {
    if constexpr (kTls) {
      // A plain-text client fails here at its first bytes; a silent one at the timeout.
      lowest().expires_after(server_->options.timeout);
      stream_.async_handshake(asio::ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code ec) {
        if (self->closed_) return;
        if (ec) {
          self->server_->tls_failures.fetch_add(1);
          self->server_->refused(self->peer(), "TLS handshake failed: " + ec.message());
          self->close();
          return;
        }
        self->read_request();
      });
    } else {
      read_request();
    }
  }

  // Closes the socket; its pending operations end with operation_aborted.
  void close() override {
    if (closed_) return;
    closed_ = true;
    wait_timer_.cancel();
    beast::error_code ignored;
    lowest().socket().shutdown(tcp::socket::shutdown_both, ignored);
    lowest().close();
    if (viewing_) {
      server_->live.remove_viewer();
      server_->stream_viewers.fetch_sub(1);
    }
    server_->forget(this->shared_from_this());
  }

  // A new sample from the live view.
  void on_frame(const std::shared_ptr<const LiveFrame>& frame) override {
    if (closed_) return;
    if (viewing_) {
      if (frame->jpeg) send_part(frame->jpeg);
      return;
    }
    if (waiting_ == HttpRoute::State) answer_state();
    else if (waiting_ == HttpRoute::Snapshot && frame->jpeg) answer_snapshot(frame->jpeg);
  }

 private:
  using Response = http::response<http::string_body>;

  void read_request() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(server_->options.max_header_bytes));
    parser_->body_limit(1024);
    lowest().expires_after(server_->options.timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (closed_) return;
    if (ec == http::error::end_of_stream || ec == asio::error::eof || ec == asio::error::connection_reset) {
      close();
      return;
    }
    if (ec == beast::error::timeout) {
      // An idle keep-alive connection (a browser's) just ends; one that
      // started a request and did not finish it is cut, and counted.
      if (buffer_.size() == 0 && !parser_->got_some()) {
        close();
        return;
      }
      server_->timed_out.fetch_add(1);
      spdlog::debug("http: {}: no complete request within {} ms; closed", peer(), server_->options.timeout.count());
      close();
      return;
    }
    if (ec) {
      server_->bad_requests.fetch_add(1);
      const bool too_large = ec == http::error::header_limit || ec == http::error::buffer_overflow;
      spdlog::debug("http: {}: bad request: {}", peer(), ec.message());
      respond(too_large ? http::status::request_header_fields_too_large
              : ec == http::error::body_limit ? http::status::payload_too_large
                                              : http::status::bad_request,
              Body::Text, fmt::format("{}\n", ec.message()), false);
      return;
    }
    handle(parser_->release());
  }

  void handle(const http::request<http::string_body>& request) {
    keep_alive_ = request.keep_alive();
    if (server_->options.access.tokens && !authorized(request)) return;
    const HttpRoute route = route_of(std::string_view(request.target().data(), request.target().size()));
    if (route == HttpRoute::NotFound) {
      respond(http::status::not_found, Body::Text, "not found: the live view serves /, /stream, /snapshot, /state, /metrics\n");
      return;
    }
    const auto method = request.method_string();
    if (std::string_view(method.data(), method.size()) != method_of(route)) {
      respond(http::status::method_not_allowed, Body::Text, fmt::format("use {}\n", method_of(route)), true,
              std::string(method_of(route)));
      return;
    }
    HttpServer::Impl& s = *server_;
    switch (route) {
      case HttpRoute::Page:
        respond(http::status::ok, Body::Html, std::string(live_view_page()));
        return;
      case HttpRoute::Metrics:
        respond(http::status::ok, Body::Metrics, metrics_text(s.metrics()));
        return;
      case HttpRoute::State: {
        const std::int64_t now = monotonic_now_ns();
        s.live.want_state_until(now + kWantedNs);
        if (s.latest && now - s.latest->summary.taken_ns < kFreshNs) {
          answer_state();
          return;
        }
        wait_for_sample(HttpRoute::State, kStateWait);
        return;
      }
      case HttpRoute::Snapshot: {
        const std::int64_t now = monotonic_now_ns();
        s.live.want_picture_until(now + kWantedNs);
        if (s.latest_picture && now - s.latest_picture->summary.taken_ns < kFreshNs) {
          answer_snapshot(s.latest_picture->jpeg);
          return;
        }
        wait_for_sample(HttpRoute::Snapshot, kSnapshotWait);
        return;
      }
      case HttpRoute::Stream:
        start_stream();
        return;
      case HttpRoute::RelearnBackground: {
        const bool taken = s.handlers.relearn_background && s.handlers.relearn_background();
        if (taken)
          respond(http::status::accepted, Body::Json,
                  R"({"relearn":true,"message":"the background is learnt again from the next frames; keep the scene empty for a moment"})");
        else
          respond(http::status::conflict, Body::Json,
                  fmt::format(R"({{"relearn":false,"message":"silhouette.background = \"{}\": only a learnt background can be re-learnt; capture a stored one with spinewatch background"}})",
                              to_string(s.station.background_mode)));
        return;
      }
      case HttpRoute::NotFound:
        return;
    }
  }

  // Authorization: Bearer <token> (RFC 6750), for every path /metrics
  // included; otherwise 401 with the challenge, counted, and the connection closed.
  bool authorized(const http::request<http::string_body>& request) {
    const auto header = request[http::field::authorization];
    std::string_view value(header.data(), header.size());
    constexpr std::string_view kScheme = "bearer ";
    std::optional<std::string> who;
    const bool bearer = value.size() > kScheme.size() &&
                        beast::iequals(beast::string_view(value.data(), kScheme.size()), beast::string_view(kScheme.data(), kScheme.size()));
    if (bearer) {
      value.remove_prefix(kScheme.size());
      while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
      who = server_->options.access.tokens->match(value);
    }
    if (who) return true;
    server_->auth_failures.fetch_add(1);
    server_->refused(peer(), bearer ? "wrong bearer token" : "no bearer token (Authorization: Bearer ...)");
    respond(http::status::unauthorized, Body::Text,
            bearer ? "unauthorized: wrong token\n" : "unauthorized: send Authorization: Bearer <token>\n", false, {},
            bearer ? R"(Bearer realm="spinewatch", error="invalid_token")" : R"(Bearer realm="spinewatch")");
    return false;
  }

  void wait_for_sample(HttpRoute what, std::chrono::milliseconds how_long) {
    waiting_ = what;
    wait_timer_.expires_after(how_long);
    wait_timer_.async_wait([self = this->shared_from_this(), what](const boost::system::error_code& ec) {
      if (ec || self->closed_ || self->waiting_ != what) return;
      if (what == HttpRoute::State) {
        self->answer_state();  // with what there is (perhaps nothing: the pipeline is stalled)
      } else if (self->server_->latest_picture) {
        self->answer_snapshot(self->server_->latest_picture->jpeg);
      } else {
        self->respond(http::status::service_unavailable, Body::Text,
                      "no picture: the station has produced no frame pair within 3 s\n");
      }
    });
  }

  void answer_state() {
    waiting_ = HttpRoute::NotFound;
    wait_timer_.cancel();
    const auto& s = *server_;
    respond(http::status::ok, Body::Json,
            state_json(s.station, s.metrics(), s.latest ? &s.latest->summary : nullptr, monotonic_now_ns()));
  }

  void answer_snapshot(const std::shared_ptr<const std::string>& jpeg) {
    waiting_ = HttpRoute::NotFound;
    wait_timer_.cancel();
    respond(http::status::ok, Body::Jpeg, *jpeg);
  }

  void respond(http::status status, Body kind, std::string body, bool keep = true,
               std::string allow = {}, std::string www_authenticate = {}) {
    auto response = std::make_shared<Response>(status, 11);
    response->set(http::field::server, "spinewatchd");
    const std::string_view type = content_type(kind);
    response->set(http::field::content_type, beast::string_view(type.data(), type.size()));
    response->set(http::field::cache_control, "no-store");
    response->set("X-Content-Type-Options", "nosniff");
    if (!allow.empty()) response->set(http::field::allow, allow);
    if (!www_authenticate.empty()) response->set(http::field::www_authenticate, www_authenticate);
    if (kind == Body::Html)
      response->set("Content-Security-Policy",
                    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src 'self'; "
                    "connect-src 'self'");
    response->body() = std::move(body);
    response->keep_alive(keep && keep_alive_);
    response->prepare_payload();
    server_->requests.fetch_add(1);
    lowest().expires_after(server_->options.timeout);
    http::async_write(stream_, *response,
                      [self = this->shared_from_this(), response](beast::error_code ec, std::size_t) {
                        if (ec == beast::error::timeout) self->server_->timed_out.fetch_add(1);
                        if (self->closed_) return;
                        if (ec || !response->keep_alive()) {
                          self->close();
                          return;
                        }
                        self->read_request();
                      });
  }

  // multipart/x-mixed-replace, as ustreamer and mjpg-streamer send it.
  void start_stream() {
    viewing_ = true;
    server_->live.add_viewer();
    server_->stream_viewers.fetch_add(1);
    server_->requests.fetch_add(1);
    beast::error_code ignored;
    lowest().socket().set_option(asio::socket_base::send_buffer_size(server_->options.stream_send_buffer), ignored);
    header_ = fmt::format(
        "HTTP/1.1 200 OK\r\nServer: spinewatchd\r\nContent-Type: multipart/x-mixed-replace;boundary={}\r\n"
        "Cache-Control: no-store\r\nPragma: no-cache\r\nConnection: close\r\nX-Content-Type-Options: nosniff\r\n\r\n",
        kBoundary);
    writing_ = true;
    lowest().expires_after(server_->options.timeout);
    asio::async_write(stream_, asio::buffer(header_), [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      self->part_written(ec, false);
    });
    // A viewer sends nothing more; reading notices when it goes. Read from
    // the socket itself, past the deadline the writes set (under TLS the
    // bytes skipped are at most the client's close_notify: nothing to answer).
    lowest().socket().async_read_some(asio::buffer(discard_), [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) self->close();
      else self->keep_discarding();
    });
  }

  void keep_discarding() {
    if (closed_) return;
    lowest().socket().async_read_some(asio::buffer(discard_), [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) self->close();
      else self->keep_discarding();
    });
  }

  void send_part(const std::shared_ptr<const std::string>& jpeg) {
    if (writing_) {
      if (pending_) server_->stream_frames_skipped.fetch_add(1);
      pending_ = jpeg;
      return;
    }
    in_flight_ = jpeg;
    part_header_ = fmt::format("--{}\r\nContent-Type: image/jpeg\r\nContent-Length: {}\r\n\r\n", kBoundary, jpeg->size());
    const std::array<asio::const_buffer, 3> buffers = {asio::buffer(part_header_), asio::buffer(*in_flight_),
                                                       asio::buffer("\r\n", 2)};
    writing_ = true;
    lowest().expires_after(server_->options.timeout);
    asio::async_write(stream_, buffers, [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      self->part_written(ec, true);
    });
  }

  void part_written(beast::error_code ec, bool frame) {
    writing_ = false;
    in_flight_.reset();
    // Counted before anything else: the timeout also ends the pending
    // read, whose handler may have closed the session already.
    if (ec == beast::error::timeout) {
      server_->timed_out.fetch_add(1);
      spdlog::warn("http: a /stream viewer took no frame for {} ms; dropped", server_->options.timeout.count());
    }
    if (closed_) return;
    if (ec) {
      close();
      return;
    }
    if (frame) server_->stream_frames.fetch_add(1);
    if (pending_) send_part(std::exchange(pending_, nullptr));
    else if (!frame && server_->latest_picture) send_part(server_->latest_picture->jpeg);
  }

  std::string peer() {
    beast::error_code ec;
    const auto p = lowest().socket().remote_endpoint(ec);
    return ec ? std::string("?") : fmt::format("{}:{}", p.address().to_string(), p.port());
  }

  beast::tcp_stream& lowest() { return beast::get_lowest_layer(stream_); }

  Stream stream_;
  std::shared_ptr<HttpServer::Impl> server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  asio::steady_timer wait_timer_;
  HttpRoute waiting_ = HttpRoute::NotFound;  // State or Snapshot while waiting for a sample
  bool keep_alive_ = false, closed_ = false, viewing_ = false, writing_ = false;
  std::string header_, part_header_;
  std::shared_ptr<const std::string> in_flight_, pending_;
  std::array<char, 256> discard_{};
};

}  // namespace http_detail
}  // namespace spinewatch
