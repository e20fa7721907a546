#include "spinewatch/daemon/endpoint.hpp"

#include <fmt/format.h>

namespace spinewatch {

Result<TcpEndpoint> parse_listen_address(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    return Error{fmt::format("\"{}\": expected HOST:PORT (e.g. 127.0.0.1:7117) or \"none\"", text)};
  std::string host = text.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string port_text = text.substr(colon + 1);
  if (port_text.find_first_not_of("0123456789") != std::string::npos || port_text.size() > 5)
    return Error{fmt::format("\"{}\": port \"{}\" is not a number in [0, 65535]", text, port_text)};
  const long port = std::stol(port_text);
  if (port > 65535) return Error{fmt::format("\"{}\": port {} is out of range [0, 65535]", text, port)};
  return TcpEndpoint{host, static_cast<std::uint16_t>(port)};
}

}  // namespace spinewatch
