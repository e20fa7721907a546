#pragma once
// Publishes NDJSON lines to every client of a TCP port and a Unix socket,
// on its own Boost.Asio thread (docs/interfaces.md §5). Each client gets the hello
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

// A group's id by name (publish.unix_socket_group); errors name `key` and the group.
Result<unsigned> group_id(const std::string& name, std::string_view key);
// posture.sock in the runtime directory: $RUNTIME_DIRECTORY (systemd), else
// /run/spinewatch when writable, else the user's (station_dirs.hpp).
Result<std::filesystem::path> default_unix_socket_path();

class Publisher {
 public:
  // Binds the sockets (removing a stale Unix socket file) and starts the I/O thread.
  static Result<std::unique_ptr<Publisher>> start(const PublisherOptions& options, std::string hello_line);
  ~Publisher();  // stop()
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  // Thread-safe; `line` without its newline.
  void publish(std::string line);
  // The hello line for clients that connect from now on.
  void set_hello(std::string line);
  // Stops accepting, gives clients a moment to receive what is queued (whole
  // lines only), closes them, removes the Unix socket file, joins. Idempotent.
  void stop();

  std::uint16_t tcp_port() const;  // the bound port (0 when TCP is off)
  std::optional<std::filesystem::path> unix_socket() const;
  PublisherStats stats() const;
  // The I/O thread's event loop, for the daemon's other servers (HTTP) to
  // run on the same thread; valid while the publisher lives, running until stop().
  boost::asio::io_context& io_context();

 private:
  Publisher();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
