#pragma once
// Where a server of the daemon listens, as the configuration and the
// command line give it: a TCP address ([publish] listen, [http] listen,
// --listen, --http); `spinewatch watch --connect` reads the same form.
#include <cstdint>
#include <string>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct TcpEndpoint {
  std::string host;        // numeric address or name, e.g. "127.0.0.1", "::"
  std::uint16_t port = 0;  // 0: any free port (tests)
};

// "HOST:PORT" ("[::1]:7117" for IPv6) → endpoint; "none" is the caller's business.
Result<TcpEndpoint> parse_listen_address(const std::string& text);

}  // namespace spinewatch
