#pragma once
// Host side of the trigger-controller box (firmware/, docs/trigger-protocol.md):
// one request line out, one OK/ERR line back, each within a deadline.
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::sync {

class SerialLine;

inline constexpr int kTriggerProtocolVersion = 1;

struct TriggerSettings {
  double rate_hz = 30.0;  // 1..120, sent with 3 decimals
  int width_us = 1000;    // 20 .. period - 100 us
  int delay_a_us = 0;     // camera A's pulse after the period start
  int delay_b_us = 0;
};

struct TriggerControllerStatus {
  double rate_hz = 0;
  int width_us = 0;
  int delay_a_us = 0;
  int delay_b_us = 0;
  bool running = false;
  std::uint64_t count = 0;  // camera A pulses since the controller's power-on
  std::uint64_t uptime_ms = 0;
};

struct TriggerControllerVersion {
  std::string firmware;  // "1.0.0"
  int protocol = 0;
};

// Reply parsers, exposed for tests; `reply` is the whole "OK ..." line.
Result<TriggerControllerStatus> parse_trigger_status(std::string_view reply);
Result<TriggerControllerVersion> parse_trigger_version(std::string_view reply);
// "30.000 Hz, 1000 us, running, 1234 pulses, up 56 s" for logs and STATUS=.
std::string describe(const TriggerControllerStatus& status);

class TriggerController {
 public:
  struct Options {
    std::chrono::milliseconds reply_timeout{500};
    // Opening the port resets Arduino-class boards (DTR); the bootloader
    // keeps the firmware from answering for up to ~2 s.
    std::chrono::milliseconds boot_wait{2500};
  };

  // Opens the serial device (115200 8N1, no flow control) and waits for the
  // controller to answer VERSION with protocol kTriggerProtocolVersion.
  static Result<std::unique_ptr<TriggerController>> open(const std::string& device, Options options);
  static Result<std::unique_ptr<TriggerController>> open(const std::string& device) { return open(device, Options{}); }
  ~TriggerController();
  TriggerController(const TriggerController&) = delete;
  TriggerController& operator=(const TriggerController&) = delete;

  Result<TriggerControllerVersion> version();
  Status configure(const TriggerSettings& settings);  // atomically, from the next period on
  Status start();
  Status stop();
  Result<TriggerControllerStatus> status();

  // One request; the text after "OK" (without the space), or an Error that
  // names the device, the request and the controller's reason.
  Result<std::string> request(std::string_view line);

  const std::string& device() const { return device_; }

 private:
  TriggerController(std::string device, std::unique_ptr<SerialLine> line, Options options);
  Error failure(std::string_view request, std::string_view problem) const;

  std::string device_;
  std::unique_ptr<SerialLine> line_;
  Options options_;
};

}  // namespace spinewatch::sync
