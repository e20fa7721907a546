#pragma once
// Slave mode: a thread reads the trigger controller's rising edges (kernel
// timestamps) and hands each edge's time to the callback.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

#include "spinewatch/sync/trigger_line.hpp"

namespace spinewatch::sync {

class TriggerSlave {
 public:
  using EdgeCallback = std::function<void(std::int64_t edge_ns)>;

  // Starts the thread. `line` must outlive the slave.
  TriggerSlave(TriggerInputLine& line, EdgeCallback on_edge);
  ~TriggerSlave();
  TriggerSlave(const TriggerSlave&) = delete;
  TriggerSlave& operator=(const TriggerSlave&) = delete;

  void stop();  // returns within one poll interval (50 ms)
  std::uint64_t edges() const { return edges_.load(); }
  std::uint64_t read_errors() const { return read_errors_.load(); }

 private:
  void run();

  TriggerInputLine& line_;
  EdgeCallback on_edge_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> edges_{0};
  std::atomic<std::uint64_t> read_errors_{0};
  std::thread thread_;
};

}  // namespace spinewatch::sync
