// Alerts on a real GPIO line (gpio-sim): postures through the alert rules
// (estimator/load/alerts.hpp) into the daemon's AlertOutput, on the
// libgpiod line the daemon opens for [alerts] gpio_chip. Lines 2 and 3 of
// the guest's gpio-sim bank (0 and 1 are the trigger tests').
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "exposure/alert_output.hpp"
#include "guest_env.hpp"
#include "spinewatch/sync/gpiod_trigger_line.hpp"

namespace spinewatch::kernel_test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr unsigned kAlertLine = 2;
constexpr unsigned kActiveLowLine = 3;

int sim_line_value(unsigned line) {
  std::ifstream in(fs::path(env_or_empty("SW_GPIO_SYSFS")) / ("sim_gpio" + std::to_string(line)) / "value");
  int v = -1;
  in >> v;
  return v;
}

// The simulated pin's pull: what it reads when nobody drives it (released).
void sim_line_pull(unsigned line, const char* pull) {
  std::ofstream out(fs::path(env_or_empty("SW_GPIO_SYSFS")) / ("sim_gpio" + std::to_string(line)) / "pull");
  out << pull;
  out.flush();
  ASSERT_TRUE(out.good()) << "writing " << pull << " to sim_gpio" << line << "/pull";
}

// Waits (an emulated CPU is slow) until the line reads `value`.
bool line_becomes(unsigned line, int value, std::chrono::milliseconds within = 3000ms) {
  const auto end = std::chrono::steady_clock::now() + within;
  while (std::chrono::steady_clock::now() < end) {
    if (sim_line_value(line) == value) return true;
    std::this_thread::sleep_for(2ms);
  }
  return sim_line_value(line) == value;
}

Posture bent(std::uint64_t seq, double inclination_deg) {
  Posture p;
  p.seq = seq;
  p.t_ns = std::int64_t(seq) * 33'333'333;
  p.state = TrackingState::Tracking;
  p.ergonomics = Ergonomics{};
  p.ergonomics->trunk_inclination_deg = inclination_deg;
  return p;
}

std::unique_ptr<AlertOutput> open_output(unsigned line, bool active_low, AlertOutputOptions options) {
  auto gpio = sync::open_gpiod_output(env_or_empty("SW_GPIO_CHIP"), line, "kernel-test-alert", active_low);
  EXPECT_TRUE(gpio.ok()) << gpio.error().message;
  if (!gpio) return nullptr;
  return std::make_unique<AlertOutput>(std::move(gpio).value(), options, "gpio-sim line " + std::to_string(line));
}

TEST(Gpio, AlertLineFollowsRaisedAndClearedAlert) {
  SW_REQUIRE_ENV("SW_GPIO_SKIP", "SW_GPIO_CHIP", "SW_GPIO_SYSFS");
  AlertRule rule;
  rule.name = "bent";
  rule.inclination_above_deg = 25.0;
  rule.hold_s = 0.2;
  rule.hysteresis_deg = 3.0;
  AlertMonitor monitor({rule});
  auto output = open_output(kAlertLine, false, {.mode = AlertSignalMode::Steady});
  ASSERT_TRUE(output);
  EXPECT_EQ(sim_line_value(kAlertLine), 0) << "requested inactive";
  std::uint64_t seq = 0;
  auto feed = [&](double deg, int frames) {
    for (int i = 0; i < frames; ++i)
      for (const AlertEvent& e : monitor.update(bent(++seq, deg))) output->on_event(e);
  };
  feed(10, 10);
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(sim_line_value(kAlertLine), 0) << "upright: no alert";
  feed(40, 12);  // 0.37 s beyond 25°: raised after 0.2 s
  EXPECT_TRUE(line_becomes(kAlertLine, 1)) << "raised: the line goes active";
  feed(23, 5);  // within the hysteresis: still raised
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(sim_line_value(kAlertLine), 1);
  feed(15, 3);  // below 22°: cleared
  EXPECT_TRUE(line_becomes(kAlertLine, 0)) << "cleared: the line goes inactive";
  feed(50, 12);
  EXPECT_TRUE(line_becomes(kAlertLine, 1));
  output.reset();  // as at SIGTERM: released inactive while the alert is up
  EXPECT_EQ(sim_line_value(kAlertLine), 0);
}

TEST(Gpio, AlertLineActiveLowPulses) {
  SW_REQUIRE_ENV("SW_GPIO_SKIP", "SW_GPIO_CHIP", "SW_GPIO_SYSFS");
  // A released line is not driven any more: it reads its pull. An active-low
  // buzzer needs a pull-up to rest silent then (docs/exposure.md), as here.
  sim_line_pull(kActiveLowLine, "pull-up");
  auto output = open_output(kActiveLowLine, true, {.mode = AlertSignalMode::Pulse, .pulse = 150ms});
  ASSERT_TRUE(output);
  EXPECT_EQ(sim_line_value(kActiveLowLine), 1) << "active low: inactive is high";
  AlertEvent raised;
  raised.rule = "bent";
  output->on_event(raised);
  // On (low) and off (high) in turn while raised.
  int changes = 0, last = sim_line_value(kActiveLowLine);
  const auto end = std::chrono::steady_clock::now() + 1500ms;
  while (std::chrono::steady_clock::now() < end) {
    const int v = sim_line_value(kActiveLowLine);
    if (v != last) ++changes;
    last = v;
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_GE(changes, 4) << "pulsing";
  AlertEvent cleared = raised;
  cleared.change = AlertChange::Cleared;
  output->on_event(cleared);
  EXPECT_TRUE(line_becomes(kActiveLowLine, 1)) << "cleared: inactive, high";
  output->set_silent(true);
  output->on_event(raised);
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(sim_line_value(kActiveLowLine), 1) << "silent: never signalled";
  output.reset();
  EXPECT_EQ(sim_line_value(kActiveLowLine), 1) << "released: the pull-up keeps it inactive";
}

}  // namespace
}  // namespace spinewatch::kernel_test
