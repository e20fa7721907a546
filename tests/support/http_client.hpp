#pragma once
// A plain POSIX HTTP/1.1 client for the live view tests (not the code under
// test): one request per connection, and an MJPEG multipart reader.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace spinewatch::test {

class HttpConnection {
 public:
  explicit HttpConnection(std::uint16_t port, int receive_buffer = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (receive_buffer > 0) ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~HttpConnection() { close(); }
  HttpConnection(const HttpConnection&) = delete;
  HttpConnection& operator=(const HttpConnection&) = delete;
  HttpConnection(HttpConnection&& o) noexcept : fd_(o.fd_), connected_(o.connected_), buffer_(std::move(o.buffer_)) {
    o.fd_ = -1;
  }

  bool connected() const { return connected_; }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  bool send(const std::string& bytes) {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // Appends what arrives within `timeout` to the buffer; false on EOF/error/timeout.
  bool receive_some(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    char chunk[65536];
    const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
    if (n <= 0) {
      eof_ = true;
      return false;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }
  // Waits until `n` bytes are buffered.
  bool receive_at_least(std::size_t n, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (buffer_.size() < n) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !receive_some(left)) return false;
    }
    return true;
  }
  // Up to and including "\r\n\r\n", removed from the buffer.
  std::optional<std::string> read_head(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      if (auto end = buffer_.find("\r\n\r\n"); end != std::string::npos) {
        std::string head = buffer_.substr(0, end + 4);
        buffer_.erase(0, end + 4);
        return head;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !receive_some(left)) return std::nullopt;
    }
  }
  std::string take(std::size_t n) {
    std::string s = buffer_.substr(0, n);
    buffer_.erase(0, n);
    return s;
  }
  // True when the server closed the connection within the timeout (data is discarded).
  bool wait_closed(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;
      char chunk[65536];
      if (::recv(fd_, chunk, sizeof chunk, 0) <= 0) return true;
    }
    return false;
  }
  std::string& buffer() { return buffer_; }
  bool eof() const { return eof_; }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  bool connected_ = false, eof_ = false;
  std::string buffer_;
};

struct HttpResponse {
  int status = 0;  // 0: no response
  std::map<std::string, std::string> headers;  // names lower-case
  std::string body;
};

inline std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

inline HttpResponse parse_head(const std::string& head) {
  HttpResponse r;
  if (head.rfind("HTTP/1.", 0) != 0 || head.size() < 12) return r;
  r.status = std::atoi(head.c_str() + 9);
  std::size_t pos = head.find("\r\n") + 2;
  while (pos < head.size()) {
    const auto end = head.find("\r\n", pos);
    if (end == std::string::npos || end == pos) break;
    const std::string line = head.substr(pos, end - pos);
    const auto colon = line.find(':');
    if (colon != std::string::npos) {
      std::string value = line.substr(colon + 1);
      while (!value.empty() && value.front() == ' ') value.erase(0, 1);
      r.headers[lower(line.substr(0, colon))] = value;
    }
    pos = end + 2;
  }
  return r;
}

// One request, "Connection: close"; the whole response.
inline HttpResponse http_request(std::uint16_t port, const std::string& method, const std::string& target,
                                 std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  HttpConnection c(port);
  if (!c.connected()) return {};
  c.send(method + " " + target + " HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n");
  const auto head = c.read_head(timeout);
  if (!head) return {};
  HttpResponse r = parse_head(*head);
  if (auto it = r.headers.find("content-length"); it != r.headers.end()) {
    const auto n = static_cast<std::size_t>(std::stoul(it->second));
    c.receive_at_least(n, timeout);
    r.body = c.take(n);
  }
  return r;
}
inline HttpResponse http_get(std::uint16_t port, const std::string& target,
                             std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  return http_request(port, "GET", target, timeout);
}

// Reads multipart/x-mixed-replace parts from a /stream response.
class MjpegReader {
 public:
  MjpegReader(std::uint16_t port, const std::string& target) : c_(port) {
    if (!c_.connected()) return;
    c_.send("GET " + target + " HTTP/1.1\r\nHost: localhost\r\n\r\n");
    if (auto head = c_.read_head(std::chrono::seconds(10))) response_ = parse_head(*head);
    const auto type = response_.headers["content-type"];
    if (auto b = type.find("boundary="); b != std::string::npos) boundary_ = type.substr(b + 9);
  }
  const HttpResponse& response() const { return response_; }
  const std::string& boundary() const { return boundary_; }

  // The next part's body; problem() says what was wrong when nothing comes.
  std::optional<std::string> next(std::chrono::milliseconds timeout) {
    const auto head = c_.read_head(timeout);
    if (!head) return fail("no part header");
    if (head->rfind("--" + boundary_ + "\r\n", 0) != 0) return fail("part does not start with the boundary: " + head->substr(0, 80));
    const HttpResponse part = parse_head("HTTP/1.1 200 OK\r\n" + head->substr(head->find("\r\n") + 2));
    auto it = part.headers.find("content-length");
    if (it == part.headers.end()) return fail("part without Content-Length");
    if (part.headers.count("content-type") == 0 || part.headers.at("content-type") != "image/jpeg")
      return fail("part is not image/jpeg");
    const auto n = static_cast<std::size_t>(std::stoul(it->second));
    if (!c_.receive_at_least(n + 2, timeout)) return fail("part body cut short");
    std::string body = c_.take(n);
    if (c_.take(2) != "\r\n") return fail("part body not followed by CRLF");
    return body;
  }
  const std::string& problem() const { return problem_; }

 private:
  std::optional<std::string> fail(std::string why) {
    problem_ = std::move(why);
    return std::nullopt;
  }
  HttpConnection c_;
  HttpResponse response_;
  std::string boundary_, problem_;
};

}  // namespace spinewatch::test
