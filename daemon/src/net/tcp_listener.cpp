#include "net/tcp_listener.hpp"

#include <fmt/format.h>

namespace spinewatch::net {

namespace asio = boost::asio;
using asio::ip::tcp;

Result<tcp::acceptor> listen_tcp(asio::io_context& io, const TcpEndpoint& where, const std::string& label) {
  boost::system::error_code ec;
  tcp::endpoint endpoint;
  auto address = asio::ip::make_address(where.host, ec);
  if (!ec) {
    endpoint = tcp::endpoint(address, where.port);
  } else {
    tcp::resolver resolver(io);
    auto results = resolver.resolve(where.host, std::to_string(where.port), ec);
    if (ec || results.empty()) return Error{fmt::format("{}: cannot resolve \"{}\": {}", label, where.host, ec.message())};
    endpoint = *results.begin();
  }
  tcp::acceptor acceptor(io);
  if (acceptor.open(endpoint.protocol(), ec); ec) return Error{fmt::format("{}: {}", label, ec.message())};
  acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (acceptor.bind(endpoint, ec); ec) return Error{fmt::format("{}: cannot bind: {}", label, ec.message())};
  if (acceptor.listen(asio::socket_base::max_listen_connections, ec); ec)
    return Error{fmt::format("{}: cannot listen: {}", label, ec.message())};
  return acceptor;
}

}  // namespace spinewatch::net
