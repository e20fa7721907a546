#pragma once
// Which network listeners must be protected (docs/security.md): one only
// this machine can reach needs nothing more; one on the network needs TLS
// and an authentication (access.hpp), unless the site has accepted it
// unprotected ([publish]/[http] allow_unauthenticated), and then every
// client is told.
#include <optional>
#include <string>
#include <string_view>

#include "access/access.hpp"
#include "spinewatch/daemon/endpoint.hpp"

namespace spinewatch {

// Only this machine can connect: a numeric loopback address (127.0.0.0/8,
// ::1) or "localhost". A name that must be resolved is not loopback.
bool is_loopback(const TcpEndpoint& endpoint);

// Reachable from the network and not protected: refused at start unless
// allow_unauthenticated (the caller's error names its own keys).
bool exposed_unprotected(const TcpEndpoint& endpoint, const Access& access);

// For a listener accepted unprotected: the warning said to every client
// and logged ("unauthenticated: tcp 0.0.0.0:7117 serves the posture stream
// to anyone who can reach it (publish.allow_unauthenticated)"); nothing
// when it is protected or loopback.
std::optional<std::string> unprotected_warning(std::string_view scheme, const TcpEndpoint& endpoint,
                                               const Access& access, std::string_view what, std::string_view key);

}  // namespace spinewatch
