#pragma once
// Master mode: a high-priority thread drives the trigger line at the frame
// rate, sleeping to absolute deadlines on CLOCK_MONOTONIC so that wake-up
// latency never accumulates into drift. Each rising edge's time goes to the
// callback (the pairer's push_trigger, through whatever queue the caller uses).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>

#include "spinewatch/sync/latency_histogram.hpp"
#include "spinewatch/sync/trigger_line.hpp"

namespace spinewatch::sync {

struct TriggerMasterOptions {
  double fps = 30.0;
  int pulse_us = 1000;
  int realtime_priority = 50;  // SCHED_FIFO priority; 0 = do not ask for real-time
};

class TriggerMaster {
 public:
  using EdgeCallback = std::function<void(std::int64_t edge_ns)>;

  // Starts the thread. `line` must outlive the master.
  TriggerMaster(TriggerOutputLine& line, TriggerMasterOptions options, EdgeCallback on_edge);
  ~TriggerMaster();  // stops and joins; leaves the line low
  TriggerMaster(const TriggerMaster&) = delete;
  TriggerMaster& operator=(const TriggerMaster&) = delete;

  void stop();
  bool realtime() const { return realtime_.load(); }
  std::uint64_t edges() const { return edges_.load(); }
  std::uint64_t line_errors() const { return line_errors_.load(); }
  // Rising-edge wake-up latency behind the absolute deadline.
  LatencySummary wake_latency() const { return latency_.summary(); }

 private:
  void run();

  TriggerOutputLine& line_;
  TriggerMasterOptions options_;
  EdgeCallback on_edge_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> realtime_{false};
  std::atomic<std::uint64_t> edges_{0};
  std::atomic<std::uint64_t> line_errors_{0};
  LatencyHistogram latency_;
  std::thread thread_;
};

}  // namespace spinewatch::sync
