#pragma once
// A blocking TLS client for the security tests: connects to 127.0.0.1,
// checks the station's certificate against the test CA, optionally
// presents a client certificate, reads lines and HTTP responses. Reads
// block until the daemon sends or closes (Asio's blocking reads wait out
// SO_RCVTIMEO): the tests only read where the daemon's own deadlines
// (auth_timeout_s, timeout_s) bound the wait, and ctest's timeout bounds the rest.
#include <sys/socket.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>

namespace spinewatch::test {

class TlsClient {
 public:
  // Throws boost::system::system_error when the connection or the handshake fails.
  TlsClient(std::uint16_t port, const std::filesystem::path& ca, const std::filesystem::path& cert = {},
            const std::filesystem::path& key = {}, std::chrono::milliseconds timeout = std::chrono::seconds(5))
      : context_(boost::asio::ssl::context::tls_client) {
    context_.load_verify_file(ca.string());
    context_.set_verify_mode(boost::asio::ssl::verify_peer);
    if (!cert.empty()) {
      context_.use_certificate_chain_file(cert.string());
      context_.use_private_key_file(key.string(), boost::asio::ssl::context::pem);
    }
    stream_.emplace(io_, context_);
    stream_->lowest_layer().connect({boost::asio::ip::make_address("127.0.0.1"), port});
    set_timeout(timeout);  // bounds connect-time writes; see above for reads
    stream_->handshake(boost::asio::ssl::stream_base::client);
  }

  void set_timeout(std::chrono::milliseconds timeout) {
    timeval tv{static_cast<time_t>(timeout.count() / 1000), static_cast<suseconds_t>(timeout.count() % 1000 * 1000)};
    ::setsockopt(stream_->lowest_layer().native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ::setsockopt(stream_->lowest_layer().native_handle(), SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  }

  bool send(const std::string& text) {
    boost::system::error_code ec;
    boost::asio::write(*stream_, boost::asio::buffer(text), ec);
    return !ec;
  }

  // The next line (without its newline), or nothing at a timeout, an error or the end.
  std::optional<std::string> read_line() {
    boost::system::error_code ec;
    const std::size_t n = boost::asio::read_until(*stream_, buffer_, '\n', ec);
    if (ec && n == 0) {
      closed_ = ec != boost::asio::error::would_block && ec != boost::asio::error::try_again;
      return std::nullopt;
    }
    std::string line(boost::asio::buffers_begin(buffer_.data()), boost::asio::buffers_begin(buffer_.data()) + n - 1);
    buffer_.consume(n);
    return line;
  }
  // Whether the last failed read ended the connection (rather than timing out).
  bool closed() const { return closed_; }

  // Everything until the daemon closes (HTTP with Connection: close).
  std::string read_all() {
    boost::system::error_code ec;
    boost::asio::read(*stream_, buffer_, ec);
    std::string all(boost::asio::buffers_begin(buffer_.data()), boost::asio::buffers_end(buffer_.data()));
    buffer_.consume(buffer_.size());
    return all;
  }

 private:
  boost::asio::io_context io_;
  boost::asio::ssl::context context_;
  std::optional<boost::asio::ssl::stream<boost::asio::ip::tcp::socket>> stream_;
  boost::asio::streambuf buffer_;
  bool closed_ = false;
};

}  // namespace spinewatch::test
