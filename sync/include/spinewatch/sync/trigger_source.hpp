#pragma once
// The trigger of the configured mode, owning its line: master drives a
// GPIO output at the camera rate, slave timestamps the trigger
// controller's rising edges, free-run has none. Every edge's time
// (CLOCK_MONOTONIC ns) goes to the callback, from the trigger's thread.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"
#include "spinewatch/sync/trigger_line.hpp"
#include "spinewatch/sync/trigger_master.hpp"
#include "spinewatch/sync/trigger_slave.hpp"

namespace spinewatch::sync {

// trigger.mode, parsed once when the configuration is read.
enum class TriggerMode : std::uint8_t {
  FreeRun,  // no trigger: the cameras run on their own clocks, frames paired by time
  Master,   // we drive a GPIO output at the camera rate
  Slave,    // we timestamp the trigger controller's rising edges on a GPIO input
};
std::string_view to_string(TriggerMode mode);

struct TriggerSourceOptions {
  TriggerMode mode = TriggerMode::FreeRun;
  std::string chip = "gpiochip0";
  unsigned line = 17;
  double fps = 30.0;
  int pulse_us = 1000;
  std::string consumer = "spinewatch";
};

class TriggerSource {
 public:
  using EdgeCallback = std::function<void(std::int64_t edge_ns)>;

  // Opens the GPIO line of the mode; nullptr for free-run. The error names
  // the chip, the line and the problem.
  static Result<std::unique_ptr<TriggerSource>> open(const TriggerSourceOptions& options, EdgeCallback on_edge);
  // Over a line the caller owns the making of (tests: a FakeTriggerLine).
  static std::unique_ptr<TriggerSource> master(std::unique_ptr<TriggerOutputLine> line, TriggerMasterOptions options,
                                               EdgeCallback on_edge);
  static std::unique_ptr<TriggerSource> slave(std::unique_ptr<TriggerInputLine> line, EdgeCallback on_edge);

  ~TriggerSource();
  TriggerSource(const TriggerSource&) = delete;
  TriggerSource& operator=(const TriggerSource&) = delete;

  void stop();
  std::uint64_t edges() const;

 private:
  TriggerSource() = default;
  // Lines first: they outlive the threads that use them.
  std::unique_ptr<TriggerOutputLine> output_;
  std::unique_ptr<TriggerInputLine> input_;
  std::unique_ptr<TriggerMaster> master_;
  std::unique_ptr<TriggerSlave> slave_;
};

}  // namespace spinewatch::sync
