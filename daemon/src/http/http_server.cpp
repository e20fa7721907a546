#include "http/http_server.hpp"

#include <future>

#include <boost/asio/ssl.hpp>

#include "http/http_session.hpp"
#include "net/tcp_listener.hpp"

namespace spinewatch {

namespace asio = boost::asio;
namespace beast = boost::beast;
using tcp = asio::ip::tcp;
using http_detail::HttpSession;
using http_detail::SessionBase;
using http_detail::TlsStream;

void HttpServer::Impl::accept_next() {
  acceptor->async_accept([self = shared_from_this()](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || self->stopped || !self->acceptor->is_open()) return;
    if (ec) {
      spdlog::error("http: accepting a connection failed: {}", ec.message());
      auto timer = std::make_shared<asio::steady_timer>(self->io, std::chrono::milliseconds(100));
      timer->async_wait([self, timer](const boost::system::error_code&) {
        if (!self->stopped) self->accept_next();
      });
      return;
    }
    self->admit(std::move(socket));
    self->accept_next();
  });
}

void HttpServer::Impl::admit(tcp::socket socket) {
  if (sessions.size() >= options.max_connections) {
    // Answered without waiting: a short reply fits any fresh socket's buffer.
    rejected.fetch_add(1);
    static constexpr std::string_view k503 =
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: 45\r\nConnection: close\r\n\r\n"
        "too many connections (http.max_connections)\n";
    boost::system::error_code ignored;
    socket.non_blocking(true, ignored);
    socket.write_some(asio::buffer(k503), ignored);
    socket.shutdown(tcp::socket::shutdown_both, ignored);
    socket.close(ignored);
    spdlog::debug("http: connection refused: {} open (http.max_connections)", sessions.size());
    return;
  }
  std::shared_ptr<SessionBase> session;
  if (options.access.tls)
    session = std::make_shared<HttpSession<TlsStream>>(TlsStream(beast::tcp_stream(std::move(socket)), *options.access.tls),
                                                       shared_from_this());
  else
    session = std::make_shared<HttpSession<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), shared_from_this());
  sessions.insert(session);
  connections.store(sessions.size());
  connections_total.fetch_add(1);
  session->start();
}

void HttpServer::Impl::forget(const std::shared_ptr<SessionBase>& session) {
  sessions.erase(session);
  connections.store(sessions.size());
}

void HttpServer::Impl::deliver(std::shared_ptr<const LiveFrame> frame) {
  if (stopped) return;
  latest = frame;
  if (frame->jpeg) latest_picture = frame;
  // A session may close (and leave `sessions`) while frames are delivered.
  std::vector<std::shared_ptr<SessionBase>> all(sessions.begin(), sessions.end());
  for (auto& s : all) s->on_frame(frame);
}

HttpServer::HttpServer(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

HttpServer::~HttpServer() { stop(); }

Result<std::unique_ptr<HttpServer>> HttpServer::start(asio::io_context& io, HttpOptions options, HttpHandlers handlers,
                                                      StationInfo station, LiveView& live) {
  auto impl = std::make_shared<Impl>(io, std::move(options), std::move(handlers), std::move(station), live);
  const TcpEndpoint& where = impl->options.endpoint;
  const std::string label = fmt::format("http {}:{}", where.host, where.port);
  auto acceptor = net::listen_tcp(io, where, label);
  if (!acceptor) return acceptor.error();
  impl->port = acceptor->local_endpoint().port();
  impl->acceptor.emplace(std::move(acceptor).value());
  // The acceptor is used from the I/O thread from here on.
  asio::post(io, [impl] { impl->accept_next(); });
  return std::unique_ptr<HttpServer>(new HttpServer(impl));
}

void HttpServer::on_frame(std::shared_ptr<const LiveFrame> frame) {
  asio::post(impl_->io, [impl = impl_, frame = std::move(frame)]() mutable { impl->deliver(std::move(frame)); });
}

void HttpServer::stop() {
  if (std::exchange(stop_called_, true)) return;
  const auto close = [impl = impl_] {
    if (impl->stopped) return;
    impl->stopped = true;
    boost::system::error_code ignored;
    if (impl->acceptor) impl->acceptor->close(ignored);
    std::vector<std::shared_ptr<SessionBase>> all(impl->sessions.begin(), impl->sessions.end());
    for (auto& s : all) s->close();
    impl->latest.reset();
    impl->latest_picture.reset();
  };
  // The loop already stopped (the daemon after a failed start): no thread
  // runs it, so the server is closed from here.
  if (impl_->io.stopped()) return close();
  auto done = std::make_shared<std::promise<void>>();
  auto future = done->get_future();
  asio::post(impl_->io, [close, done] {
    close();
    done->set_value();
  });
  // The loop may stop meanwhile (then the handler is dropped with it).
  future.wait_for(std::chrono::seconds(1));
}

std::uint16_t HttpServer::port() const { return impl_->port; }

HttpStats HttpServer::stats() const { return impl_->stats(); }

}  // namespace spinewatch