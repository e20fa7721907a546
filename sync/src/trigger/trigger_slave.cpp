#include "spinewatch/sync/trigger_slave.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

namespace spinewatch::sync {
namespace {
constexpr std::chrono::milliseconds kPollInterval{50};
}

TriggerSlave::TriggerSlave(TriggerInputLine& line, EdgeCallback on_edge) : line_(line), on_edge_(std::move(on_edge)) {
  thread_ = std::thread([this] { run(); });
}

TriggerSlave::~TriggerSlave() { stop(); }

void TriggerSlave::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void TriggerSlave::run() {
  bool logged_error = false;
  while (!stop_.load(std::memory_order_relaxed)) {
    auto edge = line_.wait_rising_edge(kPollInterval);
    if (!edge) {
      read_errors_.fetch_add(1);
      if (!logged_error) spdlog::error("trigger: {}", edge.error().message);
      logged_error = true;
      std::this_thread::sleep_for(kPollInterval);  // don't spin on a broken line
      continue;
    }
    if (!edge.value()) continue;
    edges_.fetch_add(1);
    if (on_edge_) on_edge_(*edge.value());
  }
}

}  // namespace spinewatch::sync
