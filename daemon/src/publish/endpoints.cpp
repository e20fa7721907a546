#include <grp.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>
#include <string>

#include <boost/asio/ip/address.hpp>
#include <fmt/format.h>

#include "publish/publisher.hpp"
#include "support/station_dirs.hpp"

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

bool is_loopback(const TcpEndpoint& endpoint) {
  if (endpoint.host == "localhost") return true;
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(endpoint.host, ec);
  return !ec && address.is_loopback();
}

Result<unsigned> group_id(const std::string& name, std::string_view key) {
  group entry{};
  group* found = nullptr;
  std::vector<char> buffer(16384);
  const int err = ::getgrnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found);
  if (err != 0) return Error{fmt::format("{}: cannot look up group \"{}\": {}", key, name, std::strerror(err))};
  if (found == nullptr) return Error{fmt::format("{}: no group \"{}\" on this machine (getent group {})", key, name, name)};
  return static_cast<unsigned>(found->gr_gid);
}

Result<std::filesystem::path> default_unix_socket_path() {
  return default_station_file(StationDir::Runtime, "posture.sock", "publish.unix_socket");
}

}  // namespace spinewatch
