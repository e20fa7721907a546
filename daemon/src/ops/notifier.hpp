#pragma once
// sd_notify(3) for Type=notify units. Outside systemd (no NOTIFY_SOCKET)
// every call is a cheap no-op.
#include <chrono>
#include <optional>
#include <string>

namespace spinewatch {

class SystemdNotifier {
 public:
  void ready();
  void status(const std::string& text);
  void watchdog();
  void stopping();
  // WATCHDOG_USEC for this process (sd_watchdog_enabled), when the unit sets WatchdogSec=.
  static std::optional<std::chrono::microseconds> watchdog_interval();

 private:
  bool ready_sent_ = false;
};

}  // namespace spinewatch
