#pragma once
// One connected client of the publisher (private to it). Runs only on the
// publisher's I/O thread, so it needs no locks. It owns a bounded queue of
// lines; overflowing it, or sending more than a trickle of input, ends the
// session as a drop.
#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

namespace spinewatch::detail {

using Line = std::shared_ptr<const std::string>;  // with its newline, shared by all clients

struct SessionLimits {
  std::size_t queue_lines;
  std::size_t input_bytes_per_s;
  std::size_t input_bytes_total;
};

enum class CloseKind { Normal, Dropped };

class ClientSession {
 public:
  using ClosedFn = std::function<void(ClientSession&, CloseKind, std::string_view reason)>;
  virtual ~ClientSession() = default;
  virtual void start(const Line& hello) = 0;
  virtual void deliver(const Line& line) = 0;
  // Sends what is queued, then closes (daemon stopping).
  virtual void finish() = 0;
  virtual void close(CloseKind kind, std::string_view reason) = 0;
  virtual const std::string& name() const = 0;
};

template <class Socket>
class SocketSession final : public ClientSession, public std::enable_shared_from_this<SocketSession<Socket>> {
 public:
  SocketSession(Socket socket, std::string name, SessionLimits limits, ClosedFn on_closed)
      : socket_(std::move(socket)), name_(std::move(name)), limits_(limits), on_closed_(std::move(on_closed)) {}

  void start(const Line& hello) override {
    window_start_ = std::chrono::steady_clock::now();
    queue_.push_back(hello);
    write_more();
    read_more();
  }

  void deliver(const Line& line) override {
    if (closed_ || finishing_) return;
    if (queue_.size() >= limits_.queue_lines) {
      close(CloseKind::Dropped, "did not keep up: " + std::to_string(queue_.size()) + " lines queued");
      return;
    }
    queue_.push_back(line);
    if (!writing_) write_more();
  }

  void finish() override {
    finishing_ = true;
    if (!writing_ && queue_.empty()) close(CloseKind::Normal, "daemon stopping");
  }

  void close(CloseKind kind, std::string_view reason) override {
    if (closed_) return;
    closed_ = true;
    boost::system::error_code ignored;
    socket_.close(ignored);
    queue_.clear();
    on_closed_(*this, kind, reason);
  }

  const std::string& name() const override { return name_; }

 private:
  static constexpr std::size_t kLinesPerWrite = 32;

  void write_more() {
    if (closed_) return;
    if (queue_.empty()) {
      if (finishing_) close(CloseKind::Normal, "daemon stopping");
      return;
    }
    in_flight_ = std::min(queue_.size(), kLinesPerWrite);
    buffers_.clear();
    for (std::size_t i = 0; i < in_flight_; ++i) buffers_.push_back(boost::asio::buffer(*queue_[i]));
    writing_ = true;
    boost::asio::async_write(socket_, buffers_,
                             [self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                               self->writing_ = false;
                               if (self->closed_) return;
                               if (ec) {
                                 self->close(CloseKind::Normal, "disconnected (" + ec.message() + ")");
                                 return;
                               }
                               self->queue_.erase(self->queue_.begin(),
                                                  self->queue_.begin() + static_cast<std::ptrdiff_t>(self->in_flight_));
                               self->write_more();
                             });
  }

  // Input is read only to be thrown away, and to notice a client that goes.
  void read_more() {
    socket_.async_read_some(boost::asio::buffer(input_),
                            [self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
                              if (self->closed_) return;
                              if (ec) {
                                self->close(CloseKind::Normal, ec == boost::asio::error::eof
                                                                   ? std::string("disconnected")
                                                                   : "disconnected (" + ec.message() + ")");
                                return;
                              }
                              if (auto problem = self->account_input(n)) {
                                self->close(CloseKind::Dropped, *problem);
                                return;
                              }
                              self->read_more();
                            });
  }

  std::optional<std::string> account_input(std::size_t n) {
    const auto now = std::chrono::steady_clock::now();
    if (now - window_start_ >= std::chrono::seconds(1)) {
      window_start_ = now;
      window_bytes_ = 0;
    }
    window_bytes_ += n;
    total_bytes_ += n;
    if (window_bytes_ > limits_.input_bytes_per_s)
      return "sent more than " + std::to_string(limits_.input_bytes_per_s) + " bytes in a second (clients need send nothing)";
    if (total_bytes_ > limits_.input_bytes_total)
      return "sent more than " + std::to_string(limits_.input_bytes_total) + " bytes (clients need send nothing)";
    return std::nullopt;
  }

  Socket socket_;
  std::string name_;
  SessionLimits limits_;
  ClosedFn on_closed_;
  std::deque<Line> queue_;
  std::vector<boost::asio::const_buffer> buffers_;
  std::size_t in_flight_ = 0;
  bool writing_ = false, finishing_ = false, closed_ = false;
  std::array<char, 512> input_{};
  std::chrono::steady_clock::time_point window_start_{};
  std::size_t window_bytes_ = 0, total_bytes_ = 0;
};

}  // namespace spinewatch::detail
