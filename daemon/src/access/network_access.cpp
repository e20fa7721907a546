#include "access/network_access.hpp"

#include <boost/asio/ip/address.hpp>
#include <fmt/format.h>

namespace spinewatch {

bool is_loopback(const TcpEndpoint& endpoint) {
  if (endpoint.host == "localhost") return true;
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(endpoint.host, ec);
  return !ec && address.is_loopback();
}

bool exposed_unprotected(const TcpEndpoint& endpoint, const Access& access) {
  return !is_loopback(endpoint) && !access.safe_for_network();
}

std::optional<std::string> unprotected_warning(std::string_view scheme, const TcpEndpoint& endpoint,
                                               const Access& access, std::string_view what, std::string_view key) {
  if (!exposed_unprotected(endpoint, access)) return std::nullopt;
  return fmt::format("unauthenticated: {} {}:{} serves the {} to anyone who can reach it ({})", scheme, endpoint.host,
                     endpoint.port, what, key);
}

}  // namespace spinewatch
