#pragma once
// One connected client of the publisher (private to it). Runs only on the
// network loop's thread, so it needs no locks. It owns a bounded queue of
// lines; overflowing it, or sending more than a trickle of input, ends the
// session as a drop. What the client sends is cut into lines and handed to
// the publisher's command handler, whose reply goes to this client alone.
// With tokens, the first line must be {"command":"auth","token":...}
// within the timeout; until then the client gets nothing (docs/protocol.md).
#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <spdlog/spdlog.h>

#include "access/access.hpp"
#include "publish/publisher.hpp"

namespace spinewatch::detail {

using Line = std::shared_ptr<const std::string>;  // with its newline, shared by all clients

struct SessionLimits {
  std::size_t queue_lines;
  std::size_t input_bytes_per_s;
  std::size_t input_bytes_total;  // of lines that were not accepted commands
  std::size_t input_line_bytes = 512;
};

// A line the client sent (without its newline) → the reply to it, if any,
// and whether it was a command the daemon took (those bytes do not count
// against input_bytes_total: a station's client may set the worker every
// shift for months).
using InputReply = ClientInputReply;
using InputFn = std::function<InputReply(std::string_view line, const std::string& client)>;

enum class CloseKind { Normal, Dropped };

struct SessionAuth {
  std::shared_ptr<const TokenSet> tokens;  // null: no auth line asked for
  std::chrono::milliseconds timeout{10000};
  // A refusal (the session then sends its reply and closes): counted and logged by the publisher.
  std::function<void(const std::string& client, std::string_view why)> on_failure;
};

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
  SocketSession(Socket socket, std::string name, SessionLimits limits, InputFn on_input, ClosedFn on_closed,
                SessionAuth auth = {})
      : socket_(std::move(socket)),
        name_(std::move(name)),
        limits_(limits),
        on_input_(std::move(on_input)),
        on_closed_(std::move(on_closed)),
        auth_(std::move(auth)),
        authenticated_(auth_.tokens == nullptr),
        auth_timer_(socket_.get_executor()) {}

  void start(const Line& hello) override {
    window_start_ = std::chrono::steady_clock::now();
    if (!authenticated_) {
      hello_ = hello;
      auth_timer_.expires_after(auth_.timeout);
      auth_timer_.async_wait([self = this->shared_from_this()](const boost::system::error_code& ec) {
        if (ec || self->closed_ || self->authenticated_ || self->finishing_) return;
        self->refuse("no auth line within " + std::to_string(self->auth_.timeout.count()) + " ms");
      });
    } else {
      queue_.push_back(hello);
      write_more();
    }
    read_more();
  }

  void deliver(const Line& line) override {
    if (closed_ || finishing_ || !authenticated_) return;
    if (queue_.size() >= limits_.queue_lines) {
      close(CloseKind::Dropped, "did not keep up: " + std::to_string(queue_.size()) + " lines queued");
      return;
    }
    queue_.push_back(line);
    if (!writing_) write_more();
  }

  void finish() override {
    finishing_ = true;
    if (!writing_ && queue_.empty()) close(CloseKind::Normal, finish_reason_);
  }

  void close(CloseKind kind, std::string_view reason) override {
    if (closed_) return;
    closed_ = true;
    auth_timer_.cancel();
    boost::system::error_code ignored;
    socket_.lowest_layer().close(ignored);
    queue_.clear();
    on_closed_(*this, kind, reason);
  }

  const std::string& name() const override { return name_; }

 private:
  static constexpr std::size_t kLinesPerWrite = 32;

  void write_more() {
    if (closed_) return;
    if (queue_.empty()) {
      if (finishing_) close(CloseKind::Normal, finish_reason_);
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

  // Input is read for commands (without a handler: thrown away), and to
  // notice a client that goes.
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
                              if (auto problem = self->take_lines(n)) {
                                self->close(CloseKind::Dropped, *problem);
                                return;
                              }
                              if (!self->closed_) self->read_more();
                            });
  }

  std::optional<std::string> account_input(std::size_t n) {
    const auto now = std::chrono::steady_clock::now();
    if (now - window_start_ >= std::chrono::seconds(1)) {
      window_start_ = now;
      window_bytes_ = 0;
    }
    window_bytes_ += n;
    if (window_bytes_ > limits_.input_bytes_per_s)
      return "sent more than " + std::to_string(limits_.input_bytes_per_s) + " bytes in a second (clients need send nothing)";
    return std::nullopt;
  }

  std::string too_long() const { return "sent a line longer than " + std::to_string(limits_.input_line_bytes) + " bytes"; }

  // Cuts the n new bytes into lines and answers each; a line too long to
  // be a command, or too much that was not one, ends the session.
  std::optional<std::string> take_lines(std::size_t n) {
    partial_.append(input_.data(), n);
    std::size_t start = 0;
    for (std::size_t end; (end = partial_.find('\n', start)) != std::string::npos; start = end + 1) {
      std::string_view line(partial_.data() + start, end - start);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.size() > limits_.input_line_bytes) return too_long();
      if (!authenticated_) {
        authenticate(line);
        if (closed_ || finishing_) return std::nullopt;
        continue;
      }
      const InputReply reply = on_input_ ? on_input_(line, name_) : InputReply{};
      if (!reply.accepted) total_bytes_ += line.size() + 1;
      if (reply.line) deliver(std::make_shared<const std::string>(*reply.line + "\n"));
      if (closed_) return std::nullopt;
    }
    partial_.erase(0, start);
    if (partial_.size() > limits_.input_line_bytes) return too_long();
    if (total_bytes_ > limits_.input_bytes_total)
      return "sent more than " + std::to_string(limits_.input_bytes_total) +
             " bytes that were not commands (clients need send nothing)";
    return std::nullopt;
  }

  // The first line of a client asked for a token.
  void authenticate(std::string_view line) {
    const auto token = auth_token_of(line);
    const auto who = token ? auth_.tokens->match(*token) : std::nullopt;
    if (!who) {
      refuse(token ? "wrong token" : "the first line was not {\"command\":\"auth\",\"token\":...}");
      return;
    }
    authenticated_ = true;
    auth_timer_.cancel();
    spdlog::info("publisher: client {} authenticated as {}", name_, *who);
    name_ += " as " + *who;
    queue_.push_back(std::make_shared<const std::string>(R"({"class":"reply","v":1,"command":"auth","ok":true})" "\n"));
    queue_.push_back(std::exchange(hello_, nullptr));
    if (!writing_) write_more();
  }

  // Says why (never echoing the token), then closes once that is written.
  void refuse(const std::string& why) {
    if (auth_.on_failure) auth_.on_failure(name_, why);
    queue_.push_back(std::make_shared<const std::string>(
        R"({"class":"reply","v":1,"command":"auth","ok":false,"error":")" + why_json(why) + "\"}\n"));
    finish_reason_ = "refused: " + why;
    finishing_ = true;
    if (!writing_) write_more();
  }

  static std::string why_json(const std::string& why) {
    std::string out;
    for (char c : why) {
      if (c == '"' || c == '\\') out.push_back('\\');
      out.push_back(c);
    }
    return out;
  }

  Socket socket_;
  std::string name_;
  SessionLimits limits_;
  InputFn on_input_;
  ClosedFn on_closed_;
  SessionAuth auth_;
  bool authenticated_;
  boost::asio::steady_timer auth_timer_;
  Line hello_;  // sent once the client has authenticated
  std::string finish_reason_ = "daemon stopping";
  std::string partial_;  // input after the last newline
  std::deque<Line> queue_;
  std::vector<boost::asio::const_buffer> buffers_;
  std::size_t in_flight_ = 0;
  bool writing_ = false, finishing_ = false, closed_ = false;
  std::array<char, 512> input_{};
  std::chrono::steady_clock::time_point window_start_{};
  std::size_t window_bytes_ = 0, total_bytes_ = 0;
};

}  // namespace spinewatch::detail
