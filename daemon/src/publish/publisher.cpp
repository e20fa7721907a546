#include "publish/publisher.hpp"

#include <sys/socket.h>

#include <chrono>
#include <future>
#include <map>
#include <mutex>
#include <thread>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "net/network_loop.hpp"
#include "net/tcp_listener.hpp"
#include "net/unix_listener.hpp"
#include "publish/client_session.hpp"

namespace spinewatch {

namespace asio = boost::asio;
using asio::ip::tcp;
using unix_socket = asio::local::stream_protocol;
using tls_socket = asio::ssl::stream<tcp::socket>;
using detail::CloseKind;
using detail::Line;

struct Publisher::Impl {
  Impl(asio::io_context& context, std::unique_ptr<net::NetworkLoop> loop) : own_loop(std::move(loop)), io(context) {}

  // A loop of its own (start() without one): declared first so that it is
  // destroyed last, after every socket.
  std::unique_ptr<net::NetworkLoop> own_loop;
  asio::io_context& io;
  PublisherOptions options;
  std::optional<tcp::acceptor> tcp_acceptor;
  std::optional<unix_socket::acceptor> unix_acceptor;
  std::uint16_t tcp_port = 0;
  std::map<detail::ClientSession*, std::shared_ptr<detail::ClientSession>> clients;  // I/O thread only
  Line hello;                                                                          // I/O thread only
  std::uint64_t next_client_id = 1;

  std::mutex inbox_mutex;
  std::deque<std::string> inbox;
  bool drain_posted = false;

  std::atomic<std::uint64_t> clients_now{0}, clients_total{0}, clients_dropped{0}, clients_rejected{0};
  std::atomic<std::uint64_t> auth_failures{0}, tls_failures{0};
  std::size_t handshaking = 0;     // TLS handshakes under way (I/O thread only); count against max_clients
  LogLimiter refusal_log;          // a scan or a misconfigured client must not flood the journal
  std::atomic<std::uint64_t> lines{0}, lines_dropped{0};
  bool stopped = false;
  bool owns_unix_path = false;  // only a socket we bound is removed on stop
  bool stopped_io = false;      // I/O thread: stop() has begun; handshakes still ending are not failures

  detail::SessionLimits limits() const {
    return {options.client_queue, options.max_input_bytes_per_s, options.max_input_bytes, options.max_input_line};
  }

  template <class Acceptor>
  void accept_next(Acceptor& acceptor, const char* kind) {
    acceptor.async_accept([this, &acceptor, kind](const boost::system::error_code& ec, typename Acceptor::protocol_type::socket socket) {
      if (ec == asio::error::operation_aborted || !acceptor.is_open()) return;
      if (ec) {
        // E.g. out of file descriptors: say so, back off briefly, keep serving the others.
        spdlog::error("publisher: accepting a {} client failed: {}", kind, ec.message());
        auto timer = std::make_shared<asio::steady_timer>(io, std::chrono::milliseconds(100));
        timer->async_wait([this, &acceptor, kind, timer](const boost::system::error_code&) {
          if (acceptor.is_open()) accept_next(acceptor, kind);
        });
        return;
      }
      accepted(std::move(socket));
      accept_next(acceptor, kind);
    });
  }

  void accepted(unix_socket::socket socket) {
    add_client(std::move(socket), fmt::format("#{} (unix)", next_client_id++), false);
  }

  void accepted(tcp::socket socket) {
    const std::uint64_t id = next_client_id++;
    const char* kind = options.access.tls ? "tls" : "tcp";
    std::string name = fmt::format("#{} ({})", id, kind);
    boost::system::error_code ec;
    const auto peer = socket.remote_endpoint(ec);
    if (!ec) name = fmt::format("#{} ({} {}:{})", id, kind, peer.address().to_string(), peer.port());
    if (!options.access.tls) {
      add_client(std::move(socket), std::move(name), options.access.tokens != nullptr);
      return;
    }
    if (!admissible(socket, name)) return;
    // The handshake runs beside the other clients; one that stalls or
    // speaks plain text is cut at the timeout or at its first bytes.
    ++handshaking;
    auto stream = std::make_shared<tls_socket>(std::move(socket), *options.access.tls);
    auto timer = std::make_shared<asio::steady_timer>(io, options.auth_timeout);
    timer->async_wait([stream](const boost::system::error_code& e) {
      boost::system::error_code ignored;
      if (!e) stream->lowest_layer().close(ignored);
    });
    stream->async_handshake(asio::ssl::stream_base::server,
                            [this, stream, timer, name = std::move(name)](const boost::system::error_code& e) {
                              --handshaking;
                              const bool timed_out = timer->cancel() == 0;
                              if (e || timed_out || stopped_io) {
                                if (stopped_io) return;
                                tls_failures.fetch_add(1);
                                refused(name, timed_out ? "no TLS handshake within the timeout"
                                                        : "TLS handshake failed: " + e.message());
                                boost::system::error_code ignored;
                                stream->lowest_layer().close(ignored);
                                return;
                              }
                              add_client(std::move(*stream), name, options.access.tokens != nullptr);
                            });
  }

  void refused(const std::string& name, std::string_view why) {
    // Never the token itself: only what was wrong.
    if (auto held = refusal_log.admit())
      spdlog::warn("publisher: client {} refused: {}{}", name, why,
                   *held ? fmt::format(" ({} more refusals not logged in the last 10 s)", *held) : std::string());
  }

  template <class Socket>
  bool admissible(Socket& socket, const std::string& name) {
    if (clients.size() + handshaking < options.max_clients) return true;
    clients_rejected.fetch_add(1);
    spdlog::warn("publisher: client {} refused: {} clients connected (publish.max_clients)", name,
                 clients.size() + handshaking);
    boost::system::error_code ignored;
    socket.lowest_layer().close(ignored);
    return false;
  }

  template <class Socket>
  void add_client(Socket socket, std::string name, bool needs_token) {
    if (!admissible(socket, name)) return;
    if (options.send_buffer_bytes > 0) {
      boost::system::error_code ignored;
      socket.lowest_layer().set_option(asio::socket_base::send_buffer_size(options.send_buffer_bytes), ignored);
    }
    detail::SessionAuth auth;
    if (needs_token) {
      auth.tokens = options.access.tokens;
      auth.timeout = options.auth_timeout;
      auth.on_failure = [this](const std::string& client, std::string_view why) {
        auth_failures.fetch_add(1);
        refused(client, why);
      };
    }
    auto session = std::make_shared<detail::SocketSession<Socket>>(
        std::move(socket), name, limits(), options.on_input,
        [this](detail::ClientSession& s, CloseKind kind, std::string_view reason) { on_closed(s, kind, reason); },
        std::move(auth));
    clients.emplace(session.get(), session);
    clients_now.store(clients.size());
    clients_total.fetch_add(1);
    spdlog::info("publisher: client {} connected ({} now)", name, clients.size());
    session->start(hello);
  }

  void on_closed(detail::ClientSession& session, CloseKind kind, std::string_view reason) {
    if (kind == CloseKind::Dropped) {
      clients_dropped.fetch_add(1);
      spdlog::warn("publisher: client {} dropped: {}", session.name(), reason);
    } else {
      spdlog::info("publisher: client {} {}", session.name(), reason);
    }
    // Handlers still in flight hold their own reference; this only forgets it.
    clients.erase(&session);
    clients_now.store(clients.size());
  }

  void drain() {
    std::deque<std::string> batch;
    {
      std::lock_guard lock(inbox_mutex);
      batch.swap(inbox);
      drain_posted = false;
    }
    if (batch.empty()) return;
    // A session may close (and leave `clients`) while lines are delivered.
    std::vector<std::shared_ptr<detail::ClientSession>> targets;
    targets.reserve(clients.size());
    for (auto& [key, session] : clients) targets.push_back(session);
    for (auto& text : batch) {
      const Line line = std::make_shared<const std::string>(std::move(text));
      lines.fetch_add(1, std::memory_order_relaxed);
      for (auto& session : targets) session->deliver(line);
    }
  }

  void close_acceptors() {
    boost::system::error_code ignored;
    if (tcp_acceptor) tcp_acceptor->close(ignored);
    if (unix_acceptor) unix_acceptor->close(ignored);
  }

  template <class Fn>
  void run_on_io(Fn fn) {
    std::promise<void> done;
    auto future = done.get_future();
    asio::post(io, [&] {
      fn();
      done.set_value();
    });
    future.wait();
  }
};

namespace {

Status bind_tcp(asio::io_context& io, const TcpEndpoint& where, std::optional<tcp::acceptor>& out,
                std::uint16_t& port) {
  auto acceptor = net::listen_tcp(io, where, fmt::format("listen address {}:{}", where.host, where.port));
  if (!acceptor) return acceptor.error();
  port = acceptor->local_endpoint().port();
  out.emplace(std::move(acceptor).value());
  return Ok{};
}

Status bind_unix(asio::io_context& io, const net::UnixEndpoint& where, std::optional<unix_socket::acceptor>& out) {
  auto acceptor = net::listen_unix(io, where);
  if (!acceptor) return acceptor.error();
  out.emplace(std::move(acceptor).value());
  return Ok{};
}

}  // namespace

Publisher::Publisher() = default;

Result<std::unique_ptr<Publisher>> Publisher::start(const PublisherOptions& options, std::string hello_line) {
  auto loop = std::make_unique<net::NetworkLoop>("publisher");
  asio::io_context& io = loop->io();
  return start(io, options, std::move(hello_line), std::move(loop));
}

Result<std::unique_ptr<Publisher>> Publisher::start(asio::io_context& io, const PublisherOptions& options,
                                                    std::string hello_line) {
  return start(io, options, std::move(hello_line), nullptr);
}

Result<std::unique_ptr<Publisher>> Publisher::start(asio::io_context& io, const PublisherOptions& options,
                                                    std::string hello_line, std::unique_ptr<net::NetworkLoop> own_loop) {
  std::unique_ptr<Publisher> p(new Publisher());
  p->impl_ = std::make_unique<Impl>(io, std::move(own_loop));
  Impl& impl = *p->impl_;
  impl.options = options;
  if (impl.options.client_queue == 0) impl.options.client_queue = 1;
  hello_line.push_back('\n');
  impl.hello = std::make_shared<const std::string>(std::move(hello_line));
  if (options.tcp)
    if (auto bound = bind_tcp(impl.io, *options.tcp, impl.tcp_acceptor, impl.tcp_port); !bound) return bound.error();
  if (options.unix_socket)
    if (auto bound = bind_unix(impl.io, {*options.unix_socket, options.unix_socket_gid}, impl.unix_acceptor); !bound)
      return bound.error();
  impl.owns_unix_path = impl.unix_acceptor.has_value();
  // The loop already runs: the acceptors are used from its thread from here on.
  asio::post(impl.io, [&impl] {
    if (impl.tcp_acceptor) impl.accept_next(*impl.tcp_acceptor, "tcp");
    if (impl.unix_acceptor) impl.accept_next(*impl.unix_acceptor, "unix");
  });
  return p;
}

Publisher::~Publisher() { stop(); }

void Publisher::publish(std::string line) {
  line.push_back('\n');
  bool post = false;
  {
    std::lock_guard lock(impl_->inbox_mutex);
    if (impl_->stopped) return;
    if (impl_->inbox.size() >= impl_->options.inbox) {
      impl_->inbox.pop_front();
      impl_->lines_dropped.fetch_add(1, std::memory_order_relaxed);
    }
    impl_->inbox.push_back(std::move(line));
    if (!impl_->drain_posted) post = impl_->drain_posted = true;
  }
  if (post) asio::post(impl_->io, [impl = impl_.get()] { impl->drain(); });
}

void Publisher::set_hello(std::string line) {
  line.push_back('\n');
  asio::post(impl_->io, [impl = impl_.get(), l = std::make_shared<const std::string>(std::move(line))] { impl->hello = l; });
}

void Publisher::stop() {
  Impl& impl = *impl_;
  {
    std::lock_guard lock(impl.inbox_mutex);
    if (impl.stopped) return;
    impl.stopped = true;
  }
  // A clean end for clients while the loop runs; the daemon stops its
  // servers before its network loop.
  if (!impl.io.stopped()) {
    impl.run_on_io([&] {
      impl.stopped_io = true;
      impl.drain();
      impl.close_acceptors();
      std::vector<std::shared_ptr<detail::ClientSession>> all;
      for (auto& [key, s] : impl.clients) all.push_back(s);
      for (auto& s : all) s->finish();
    });
    // Clients that read get what is queued, as whole lines; the rest are cut off.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (impl.clients_now.load() > 0 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    impl.run_on_io([&] {
      std::vector<std::shared_ptr<detail::ClientSession>> all;
      for (auto& [key, s] : impl.clients) all.push_back(s);
      for (auto& s : all) s->close(CloseKind::Normal, "daemon stopped");
    });
  }
  if (impl.own_loop) impl.own_loop->stop();
  // No thread runs the loop any more (else they were closed on it above).
  if (impl.io.stopped()) impl.close_acceptors();
  if (impl.owns_unix_path) {
    std::error_code ignored;
    std::filesystem::remove(*impl.options.unix_socket, ignored);
  }
}

asio::io_context& Publisher::io_context() { return impl_->io; }

std::uint16_t Publisher::tcp_port() const { return impl_->tcp_port; }

std::optional<std::filesystem::path> Publisher::unix_socket() const { return impl_->options.unix_socket; }

PublisherStats Publisher::stats() const {
  PublisherStats s;
  s.clients = impl_->clients_now.load();
  s.clients_total = impl_->clients_total.load();
  s.clients_dropped = impl_->clients_dropped.load();
  s.clients_rejected = impl_->clients_rejected.load();
  s.auth_failures = impl_->auth_failures.load();
  s.tls_failures = impl_->tls_failures.load();
  s.lines = impl_->lines.load();
  s.lines_dropped = impl_->lines_dropped.load();
  {
    std::lock_guard lock(impl_->inbox_mutex);
    s.inbox = impl_->inbox.size();
  }
  s.inbox_capacity = impl_->options.inbox;
  return s;
}

}  // namespace spinewatch
