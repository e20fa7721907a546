#pragma once
// A trigger line in memory, for tests and benchmarks: records what a master
// drives onto it, and delivers edges a test injects to a slave.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "spinewatch/sync/trigger_line.hpp"

namespace spinewatch::sync {

class FakeTriggerLine final : public TriggerOutputLine, public TriggerInputLine {
 public:
  struct Transition {
    bool high;
    std::int64_t t_ns;  // CLOCK_MONOTONIC when set() was called
  };

  Status set(bool high) override;
  Result<std::optional<std::int64_t>> wait_rising_edge(std::chrono::nanoseconds timeout) override;

  void inject_rising_edge(std::int64_t t_ns);
  void fail_next_reads(int count);  // wait_rising_edge returns an error this many times
  std::vector<Transition> transitions() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable edge_ready_;
  std::vector<Transition> transitions_;
  std::deque<std::int64_t> edges_;
  int failures_ = 0;
};

}  // namespace spinewatch::sync
