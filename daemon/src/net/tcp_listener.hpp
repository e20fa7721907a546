#pragma once
// A listening TCP socket for one of the daemon's servers (the posture
// stream, HTTP): resolves the host when it is a name, binds, listens.
// Errors start with `label` (e.g. "listen address 0.0.0.0:7117").
#include <string>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>

#include "spinewatch/daemon/endpoint.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::net {

Result<boost::asio::ip::tcp::acceptor> listen_tcp(boost::asio::io_context& io, const TcpEndpoint& where,
                                                  const std::string& label);

}  // namespace spinewatch::net
