#include "net/network_loop.hpp"

#include <exception>

#include <spdlog/spdlog.h>

namespace spinewatch::net {

NetworkLoop::NetworkLoop(std::string name) : name_(std::move(name)), work_(io_.get_executor()) {
  thread_ = std::thread([this] {
    for (;;) {
      try {
        io_.run();
        return;
      } catch (const std::exception& e) {
        spdlog::error("{}: {}", name_, e.what());  // one client's fault: keep serving the others
      }
    }
  });
}

NetworkLoop::~NetworkLoop() { stop(); }

void NetworkLoop::stop() {
  if (!thread_.joinable()) return;
  work_.reset();
  io_.stop();
  thread_.join();
}

}  // namespace spinewatch::net
