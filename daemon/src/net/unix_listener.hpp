#pragma once
// A listening Unix socket for the posture stream: its file (a stale one
// removed, a live daemon's never stolen), mode 0660, given to a group.
// Who may connect is the file's business (docs/security.md).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::net {

struct UnixEndpoint {
  std::filesystem::path path;
  std::optional<unsigned> gid;  // the file's group after bind; unset: the daemon's own
};

// Binds and listens; errors name the path and, where one helps, the key or
// option that changes it.
Result<boost::asio::local::stream_protocol::acceptor> listen_unix(boost::asio::io_context& io, const UnixEndpoint& where);

}  // namespace spinewatch::net

namespace spinewatch {

// A group's id by name (publish.unix_socket_group); errors name `key` and the group.
Result<unsigned> group_id(const std::string& name, std::string_view key);
// posture.sock in the runtime directory: $RUNTIME_DIRECTORY (systemd), else
// /run/spinewatch when writable, else the user's (station_dirs.hpp).
Result<std::filesystem::path> default_unix_socket_path();

}  // namespace spinewatch
