#pragma once
// Publishes NDJSON lines to every client of a TCP port and a Unix socket,
// on the daemon's network loop (docs/interfaces.md §5). Each client gets the hello
// line first, then every published line in order. A client that does not
// keep up overflows its bounded queue and is dropped; what clients send is
// cut into lines for the command handler (or thrown away without one), and
// a client that sends too much is dropped too.
// publish() never blocks on a socket: the pipeline and the other clients
// never wait for anyone.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "access/access.hpp"
#include "spinewatch/daemon/endpoint.hpp"
#include "spinewatch/frames/result.hpp"

namespace boost::asio {
class io_context;
}

namespace spinewatch::net {
class NetworkLoop;
}

namespace spinewatch {

// What the publisher does with one line a client sent.
struct ClientInputReply {
  std::optional<std::string> line;  // sent to that client alone (without its newline)
  bool accepted = false;            // a command taken: not counted against max_input_bytes
};

struct PublisherOptions {
  std::optional<TcpEndpoint> tcp;
  std::optional<std::filesystem::path> unix_socket;
  // The socket file's group after bind (mode 0660 either way); unset: the daemon's own.
  std::optional<unsigned> unix_socket_gid;
  std::size_t client_queue = 256;  // lines queued per client before it is dropped
  std::size_t max_clients = 32;    // further connections are closed at once
  std::size_t inbox = 1024;        // lines waiting for the I/O thread (oldest dropped)
  // Clients need send nothing; a client that sends more than this in any
  // one-second window, or more than max_input_bytes in all that were not
  // accepted commands, or a line longer than max_input_line, is dropped.
  std::size_t max_input_bytes_per_s = 1024;
  std::size_t max_input_bytes = 16 * 1024;
  std::size_t max_input_line = 512;
  // Each line a client sends, on the I/O thread (it must not block): the
  // reply for that client alone, and whether it was an accepted command.
  // Unset: input is read and thrown away.
  std::function<ClientInputReply(std::string_view line, const std::string& client)> on_input;
  int send_buffer_bytes = 0;  // SO_SNDBUF for client sockets; 0: the kernel's default
  // The TCP listener's TLS and authentication (docs/security.md); the Unix
  // socket is guarded by its file mode and group instead. A TLS handshake,
  // and with tokens the auth line, must complete within auth_timeout.
  Access access{};
  std::chrono::milliseconds auth_timeout{10000};
};

struct PublisherStats {
  std::uint64_t clients = 0;           // connected now
  std::uint64_t clients_total = 0;     // accepted since start
  std::uint64_t clients_dropped = 0;   // dropped for a queue overflow or too much input
  std::uint64_t clients_rejected = 0;  // refused because max_clients were connected
  std::uint64_t auth_failures = 0;     // TCP clients closed: no valid token within the timeout
  std::uint64_t tls_failures = 0;      // TCP clients closed: the TLS handshake failed (plain text, no or a foreign certificate)
  std::uint64_t lines = 0;             // lines published
  std::uint64_t lines_dropped = 0;     // lines dropped from the inbox (I/O thread behind)
  std::size_t inbox = 0;               // lines waiting for the I/O thread now
  std::size_t inbox_capacity = 0;
};

class Publisher {
 public:
  // Binds the sockets (removing a stale Unix socket file) and serves its
  // clients on `io`, the daemon's network loop (net/network_loop.hpp),
  // which must run until stop() has returned and stop before the
  // publisher is destroyed.
  static Result<std::unique_ptr<Publisher>> start(boost::asio::io_context& io, const PublisherOptions& options,
                                                  std::string hello_line);
  // The same on a network loop of its own, stopped with the publisher
  // (tests; a program with no other server).
  static Result<std::unique_ptr<Publisher>> start(const PublisherOptions& options, std::string hello_line);
  ~Publisher();  // stop()
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  // Thread-safe; `line` without its newline.
  void publish(std::string line);
  // The hello line for clients that connect from now on.
  void set_hello(std::string line);
  // Stops accepting, gives clients a moment to receive what is queued (whole
  // lines only), closes them, removes the Unix socket file; a loop of its
  // own is stopped too. Once the loop has stopped, clients are just cut
  // off. Idempotent; not from the loop's thread.
  void stop();

  std::uint16_t tcp_port() const;  // the bound port (0 when TCP is off)
  std::optional<std::filesystem::path> unix_socket() const;
  PublisherStats stats() const;
  // The event loop it serves on (tests hold its thread with it).
  boost::asio::io_context& io_context();

 private:
  Publisher();
  static Result<std::unique_ptr<Publisher>> start(boost::asio::io_context& io, const PublisherOptions& options,
                                                  std::string hello_line, std::unique_ptr<net::NetworkLoop> own_loop);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
