#pragma once
// The trigger box (trigger.controller, docs/sync.md): set up at start for
// the camera rate and pulse width, then asked for its STATUS once a second
// on the control thread (~10 ms at 115200 baud, at most the 500 ms reply
// timeout). A box that cannot be opened or set up (unplugged, still
// booting) is tried again every kRetry; the daemon runs on meanwhile, its
// status line saying why there are no pairs. A failure is logged when it
// starts and when it ends, not every second.
#include <chrono>
#include <memory>
#include <string>

#include "spinewatch/daemon/config.hpp"
#include "spinewatch/sync/trigger_controller.hpp"

namespace spinewatch {

class TriggerMonitor {
 public:
  explicit TriggerMonitor(const Config& config);
  bool configured() const { return !device_.empty(); }
  // Control thread: open and start the box if need be, then read its status.
  void poll();
  // For the status line: the box's last STATUS, "error: …", or "" before the first.
  std::string status() const;

 private:
  enum class State { NotAsked, Answering, Failing };
  static constexpr std::chrono::seconds kRetry{5};
  void fail(std::string message);

  std::string device_;
  double rate_hz_;
  int pulse_us_;
  std::unique_ptr<sync::TriggerController> controller_;
  State state_ = State::NotAsked;
  std::string text_;  // Answering: the STATUS described; Failing: the error
  std::chrono::steady_clock::time_point next_attempt_{};
};

}  // namespace spinewatch
