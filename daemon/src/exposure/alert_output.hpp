#pragma once
// Alerts signalled on an output line — a buzzer or a lamp on a GPIO pin
// (docs/exposure.md, "Signalling alerts on a GPIO line"). The estimator
// thread hands over each raised or cleared alert (a set update under a
// short lock); the output's own thread drives the line, so a slow or
// failing GPIO write never delays a pair. The line is driven inactive at
// stop() and when the object goes (RAII), whatever was raised.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>

#include "spinewatch/daemon/config.hpp"  // AlertSignalMode
#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/sync/trigger_line.hpp"

namespace spinewatch {

struct AlertOutputOptions {
  AlertSignalMode mode = AlertSignalMode::Steady;
  std::chrono::milliseconds pulse{500};  // Pulse: the length of each on and each off
  bool silent = false;                   // record alerts, never signal them
};

struct AlertOutputStats {
  std::uint64_t signalled = 0;     // times the line went from idle to signalling
  std::uint64_t write_errors = 0;  // writes the line refused (logged when they start and stop)
  bool signalling = false;         // the line is being driven for an alert now
};

class AlertOutput {
 public:
  // `name` says which line in log messages ("GPIO gpiochip0 line 17").
  AlertOutput(std::unique_ptr<sync::TriggerOutputLine> line, AlertOutputOptions options, std::string name);
  ~AlertOutput();  // stop()
  AlertOutput(const AlertOutput&) = delete;
  AlertOutput& operator=(const AlertOutput&) = delete;

  // Estimator thread: a rule raised or cleared. Never waits on the line.
  void on_event(const AlertEvent& event);
  // Any thread (a SIGHUP reload): silent drives the line inactive at once
  // and keeps it so; back to signalling, alerts still raised are signalled.
  void set_silent(bool silent);
  bool silent() const;
  // Drives the line inactive, joins the thread, releases the line. Idempotent.
  void stop();

  AlertOutputStats stats() const;
  const std::string& name() const { return name_; }

 private:
  void run();
  void write(bool active, bool& driven);

  std::unique_ptr<sync::TriggerOutputLine> line_;
  const AlertOutputOptions options_;
  const std::string name_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::set<std::string> raised_;  // rules raised now
  bool silent_;
  bool stopping_ = false;
  AlertOutputStats stats_;
  bool failing_ = false;  // output thread only: the last write failed

  std::thread thread_;  // last: started once everything above is set up
};

}  // namespace spinewatch
