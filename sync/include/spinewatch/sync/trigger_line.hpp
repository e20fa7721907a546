#pragma once
// One GPIO line of the trigger, behind our own interface so that the
// libgpiod 1.6 binding (gpiod_trigger_line.hpp) can be joined by a 2.x one
// and tests can use a fake line.
#include <chrono>
#include <cstdint>
#include <optional>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::sync {

// Master mode: we drive the cameras' trigger inputs.
class TriggerOutputLine {
 public:
  virtual ~TriggerOutputLine() = default;
  virtual Status set(bool high) = 0;
};

// Slave mode: an external controller drives the line; we read its rising edges.
class TriggerInputLine {
 public:
  virtual ~TriggerInputLine() = default;
  // The next rising edge's time (CLOCK_MONOTONIC ns), nothing on timeout.
  virtual Result<std::optional<std::int64_t>> wait_rising_edge(std::chrono::nanoseconds timeout) = 0;
};

}  // namespace spinewatch::sync
