#include "controller/serial_line.hpp"

#include <termios.h>

#include <algorithm>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

namespace spinewatch::sync {

namespace asio = boost::asio;

namespace {
constexpr std::size_t kMaxLine = 4096;  // a peer that never sends '\n' cannot grow us without bound
}

struct SerialLine::Impl {
  asio::io_context io;
  asio::serial_port port{io};
  asio::streambuf input{kMaxLine};

  // Runs the pending operation until `done` or the deadline; on timeout the
  // operation is cancelled and its handler drained, so the port is reusable.
  bool run_until(const bool& done, std::chrono::milliseconds timeout) {
    io.restart();
    io.run_for(timeout);
    if (done) return true;
    boost::system::error_code ignored;
    port.cancel(ignored);
    io.restart();
    io.run();
    return done;
  }

  std::optional<std::string> take_buffered_line() {
    const auto begin = asio::buffers_begin(input.data());
    const auto end = asio::buffers_end(input.data());
    const auto nl = std::find(begin, end, '\n');
    if (nl == end) return std::nullopt;
    std::string line(begin, nl);
    input.consume(line.size() + 1);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }
};

SerialLine::SerialLine(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SerialLine::~SerialLine() = default;

Result<std::unique_ptr<SerialLine>> SerialLine::open(const std::string& device, unsigned baud) {
  auto impl = std::make_unique<Impl>();
  boost::system::error_code ec;
  impl->port.open(device, ec);
  if (ec) return Error{"cannot open: " + ec.message()};
  using sp = asio::serial_port_base;
  impl->port.set_option(sp::baud_rate(baud), ec);
  if (!ec) impl->port.set_option(sp::character_size(8), ec);
  if (!ec) impl->port.set_option(sp::parity(sp::parity::none), ec);
  if (!ec) impl->port.set_option(sp::stop_bits(sp::stop_bits::one), ec);
  if (!ec) impl->port.set_option(sp::flow_control(sp::flow_control::none), ec);
  if (ec) return Error{"cannot set 115200 8N1: " + ec.message()};
  return std::unique_ptr<SerialLine>(new SerialLine(std::move(impl)));
}

Status SerialLine::write_line(std::string_view line, std::chrono::milliseconds timeout) {
  std::string out(line);
  out += '\n';
  bool done = false;
  boost::system::error_code result;
  asio::async_write(impl_->port, asio::buffer(out), [&](const boost::system::error_code& ec, std::size_t) {
    result = ec;
    done = true;
  });
  if (!impl_->run_until(done, timeout) || result == asio::error::operation_aborted)
    return Error{"write timed out after " + std::to_string(timeout.count()) + " ms"};
  if (result) return Error{"write failed: " + result.message()};
  return Ok{};
}

Result<std::optional<std::string>> SerialLine::read_line(std::chrono::milliseconds timeout) {
  if (auto line = impl_->take_buffered_line()) return line;
  bool done = false;
  boost::system::error_code result;
  asio::async_read_until(impl_->port, impl_->input, '\n', [&](const boost::system::error_code& ec, std::size_t) {
    result = ec;
    done = true;
  });
  if (!impl_->run_until(done, timeout) || result == asio::error::operation_aborted)
    return std::optional<std::string>{};
  if (result == asio::error::not_found) {
    impl_->input.consume(impl_->input.size());
    return Error{"a reply longer than " + std::to_string(kMaxLine) + " bytes without a line end"};
  }
  if (result) return Error{"read failed: " + result.message()};
  return impl_->take_buffered_line();
}

void SerialLine::discard_input() {
  impl_->input.consume(impl_->input.size());
  ::tcflush(impl_->port.native_handle(), TCIFLUSH);
}

}  // namespace spinewatch::sync
