#include "spinewatch/sync/gpiod_trigger_line.hpp"

#include <bitset>
#include <exception>
#include <optional>

#include <fmt/format.h>
#include <gpiod.hpp>
#include <spdlog/spdlog.h>

#include "spinewatch/sync/edge_clock.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch::sync {
namespace {

Error gpio_error(const std::string& chip, unsigned line, const std::exception& e) {
  return Error{fmt::format("GPIO {} line {}: {}", chip, line, e.what())};
}

class GpiodOutput final : public TriggerOutputLine {
 public:
  GpiodOutput(gpiod::chip chip, gpiod::line line, std::string name)
      : chip_(std::move(chip)), line_(std::move(line)), name_(std::move(name)) {}
  ~GpiodOutput() override {
    try {
      line_.set_value(0);
      line_.release();
    } catch (const std::exception&) {  // the chip may be gone; nothing left to do
    }
  }
  Status set(bool high) override {
    try {
      line_.set_value(high ? 1 : 0);
      return Ok{};
    } catch (const std::exception& e) {
      return Error{fmt::format("{}: cannot set the line: {}", name_, e.what())};
    }
  }

 private:
  gpiod::chip chip_;  // keeps the line's chip open
  gpiod::line line_;
  std::string name_;
};

class GpiodInput final : public TriggerInputLine {
 public:
  GpiodInput(gpiod::chip chip, gpiod::line line, std::string name)
      : chip_(std::move(chip)), line_(std::move(line)), name_(std::move(name)) {}
  ~GpiodInput() override {
    try {
      line_.release();
    } catch (const std::exception&) {
    }
  }

  Result<std::optional<std::int64_t>> wait_rising_edge(std::chrono::nanoseconds timeout) override {
    try {
      if (!line_.event_wait(timeout)) return std::optional<std::int64_t>{};
      const gpiod::line_event event = line_.event_read();
      const std::int64_t mono = monotonic_now_ns();
      const std::int64_t real = realtime_now_ns();
      const std::int64_t stamp = event.timestamp.count();
      if (!clock_) {
        clock_ = classify_edge_clock(stamp, mono, real);
        if (*clock_ == EdgeClock::Realtime) {
          spdlog::warn("{}: kernel GPIO event timestamps are CLOCK_REALTIME (Linux < 5.7); converting to "
                       "CLOCK_MONOTONIC, a clock step during capture will shift edges", name_);
        } else {
          spdlog::info("{}: kernel GPIO event timestamps are CLOCK_MONOTONIC", name_);
        }
      }
      if (event.event_type != gpiod::line_event::RISING_EDGE) return std::optional<std::int64_t>{};
      return std::optional<std::int64_t>{to_monotonic(*clock_, stamp, mono, real)};
    } catch (const std::exception& e) {
      return Error{fmt::format("{}: cannot read events: {}", name_, e.what())};
    }
  }

 private:
  gpiod::chip chip_;
  gpiod::line line_;
  std::string name_;
  std::optional<EdgeClock> clock_;
};

Result<std::pair<gpiod::chip, gpiod::line>> find_line(const std::string& chip_name, unsigned offset) {
  try {
    gpiod::chip chip(chip_name);
    if (offset >= chip.num_lines()) {
      return Error{fmt::format("GPIO {}: no line {} (the chip has {})", chip_name, offset, chip.num_lines())};
    }
    gpiod::line line = chip.get_line(offset);
    return std::make_pair(std::move(chip), std::move(line));
  } catch (const std::exception& e) {
    return gpio_error(chip_name, offset, e);
  }
}

}  // namespace

Result<std::unique_ptr<TriggerOutputLine>> open_gpiod_output(const std::string& chip, unsigned line,
                                                             const std::string& consumer, bool active_low) {
  auto found = find_line(chip, line);
  if (!found) return found.error();
  try {
    // With FLAG_ACTIVE_LOW the kernel inverts the values: 0 stays "inactive"
    // for the request's default and the destructor's release alike.
    const std::bitset<32> flags = active_low ? gpiod::line_request::FLAG_ACTIVE_LOW : std::bitset<32>{};
    found->second.request({consumer, gpiod::line_request::DIRECTION_OUTPUT, flags}, 0);
  } catch (const std::exception& e) {
    return gpio_error(chip, line, e);
  }
  return std::unique_ptr<TriggerOutputLine>(std::make_unique<GpiodOutput>(
      std::move(found->first), std::move(found->second), fmt::format("GPIO {} line {}", chip, line)));
}

Result<std::unique_ptr<TriggerInputLine>> open_gpiod_input(const std::string& chip, unsigned line,
                                                           const std::string& consumer) {
  auto found = find_line(chip, line);
  if (!found) return found.error();
  try {
    found->second.request({consumer, gpiod::line_request::EVENT_RISING_EDGE, 0});
  } catch (const std::exception& e) {
    return gpio_error(chip, line, e);
  }
  return std::unique_ptr<TriggerInputLine>(std::make_unique<GpiodInput>(
      std::move(found->first), std::move(found->second), fmt::format("GPIO {} line {}", chip, line)));
}

}  // namespace spinewatch::sync
