#include "net/unix_listener.hpp"

#include <grp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "support/station_dirs.hpp"

namespace spinewatch::net {

namespace asio = boost::asio;
using unix_socket = asio::local::stream_protocol;

namespace {

// A socket file left by a daemon that died is removed; one that a live
// daemon still answers on is not stolen.
Status remove_stale_socket(asio::io_context& io, const std::filesystem::path& path) {
  std::error_code fs_ec;
  const auto status = std::filesystem::symlink_status(path, fs_ec);
  if (fs_ec || !std::filesystem::exists(status)) return Ok{};
  if (!std::filesystem::is_socket(status))
    return Error{fmt::format("unix socket {}: exists and is not a socket", path.string())};
  unix_socket::socket probe(io);
  boost::system::error_code ec;
  probe.connect(unix_socket::endpoint(path.string()), ec);
  if (!ec) return Error{fmt::format("unix socket {}: another process is listening on it", path.string())};
  if (!std::filesystem::remove(path, fs_ec) && fs_ec)
    return Error{fmt::format("unix socket {}: cannot remove the stale socket: {}", path.string(), fs_ec.message())};
  spdlog::info("publisher: removed stale socket {}", path.string());
  return Ok{};
}

}  // namespace

Result<unix_socket::acceptor> listen_unix(asio::io_context& io, const UnixEndpoint& where) {
  const std::filesystem::path& path = where.path;
  const std::optional<unsigned>& gid = where.gid;
  if (auto removed = remove_stale_socket(io, path); !removed) return removed.error();
  boost::system::error_code ec;
  unix_socket::acceptor acceptor(io);
  if (acceptor.open(unix_socket(), ec); ec) return Error{fmt::format("unix socket {}: {}", path.string(), ec.message())};
  if (acceptor.bind(unix_socket::endpoint(path.string()), ec); ec)
    return Error{fmt::format("unix socket {}: cannot bind: {} (--unix PATH or [publish] unix_socket chooses another "
                             "path, --unix none turns the socket off)", path.string(), ec.message())};
  if (::chmod(path.c_str(), 0660) != 0)
    return Error{fmt::format("unix socket {}: cannot set mode 0660: {}", path.string(), std::strerror(errno))};
  // Readers in that group (systemd: SupplementaryGroups=) may connect; a
  // process may give its file to any group it is a member of.
  if (gid && ::chown(path.c_str(), static_cast<uid_t>(-1), static_cast<gid_t>(*gid)) != 0)
    return Error{fmt::format("unix socket {}: cannot give it to group {} (publish.unix_socket_group; the daemon must be "
                             "a member): {}", path.string(), *gid, std::strerror(errno))};
  if (acceptor.listen(asio::socket_base::max_listen_connections, ec); ec)
    return Error{fmt::format("unix socket {}: cannot listen: {}", path.string(), ec.message())};
  return acceptor;
}

}  // namespace spinewatch::net

namespace spinewatch {

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
