// Alerts on an output line (daemon/alert_output.hpp) with the fake line of
// spinewatch_sync_testing: active while an alert is raised, pulsed as
// configured, never touched in silent mode, inactive at stop; and the
// [alerts] keys of the output and of silent mode (docs/exposure.md).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "exposure/alert_output.hpp"
#include "ops/config_reload.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/load/alert_json.hpp"
#include "spinewatch/sync/fake_trigger_line.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using Transitions = std::vector<sync::FakeTriggerLine::Transition>;

// The output owns its line and releases it at stop; the test keeps the
// fake behind it to read what was driven, and can make writes fail.
class SharedLine final : public sync::TriggerOutputLine {
 public:
  SharedLine(std::shared_ptr<sync::FakeTriggerLine> fake, std::shared_ptr<std::atomic<bool>> fail)
      : fake_(std::move(fake)), fail_(std::move(fail)) {}
  ~SharedLine() override { (void)fake_->set(false); }  // as the gpiod line: inactive when released
  Status set(bool high) override {
    if (fail_->load()) return Error{"fake line: write refused"};
    return fake_->set(high);
  }

 private:
  std::shared_ptr<sync::FakeTriggerLine> fake_;
  std::shared_ptr<std::atomic<bool>> fail_;
};

struct Rig {
  std::shared_ptr<sync::FakeTriggerLine> fake = std::make_shared<sync::FakeTriggerLine>();
  std::shared_ptr<std::atomic<bool>> fail = std::make_shared<std::atomic<bool>>(false);
  std::unique_ptr<AlertOutput> output;

  explicit Rig(AlertOutputOptions options) {
    output = std::make_unique<AlertOutput>(std::make_unique<SharedLine>(fake, fail), options, "fake line");
  }
  // Waits (scaled for sanitizer builds) until `n` transitions were driven.
  Transitions wait_for(std::size_t n) const {
    const auto deadline = std::chrono::steady_clock::now() + test::scaled(2s);
    while (fake->transitions().size() < n && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(1ms);
    return fake->transitions();
  }
  bool high() const {
    auto t = fake->transitions();
    return !t.empty() && t.back().high;
  }
};

AlertEvent event(const std::string& rule, AlertChange change) {
  AlertEvent e;
  e.rule = rule;
  e.change = change;
  return e;
}

TEST(AlertOutput, SteadyIsActiveWhileAnyAlertIsRaised) {
  Rig rig({.mode = AlertSignalMode::Steady});
  std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(rig.fake->transitions().empty()) << "nothing raised: the line stays inactive";
  rig.output->on_event(event("stooped", AlertChange::Raised));
  auto t = rig.wait_for(1);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_TRUE(t[0].high);
  EXPECT_TRUE(rig.output->stats().signalling);
  // A second rule raised, then the first cleared: still an alert up.
  rig.output->on_event(event("twist_while_flexed", AlertChange::Raised));
  rig.output->on_event(event("stooped", AlertChange::Cleared));
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(rig.fake->transitions().size(), 1u);
  rig.output->on_event(event("twist_while_flexed", AlertChange::Cleared));
  t = rig.wait_for(2);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_FALSE(t[1].high);
  EXPECT_EQ(rig.output->stats().signalled, 1u);
  EXPECT_EQ(rig.output->stats().write_errors, 0u);
}

TEST(AlertOutput, PulsesOnAndOffAsConfiguredThenStopsInactive) {
  const auto pulse = 40ms;
  Rig rig({.mode = AlertSignalMode::Pulse, .pulse = pulse});
  rig.output->on_event(event("stooped", AlertChange::Raised));
  auto t = rig.wait_for(5);
  ASSERT_GE(t.size(), 5u);
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_EQ(t[i].high, i % 2 == 0) << "alternates, starting on";
  // The k-th change comes k pulses after the first at the earliest (a loaded
  // machine may make it later, never earlier; the slack is the first write's own latency).
  const std::int64_t pulse_ns = std::chrono::nanoseconds(pulse).count();
  for (std::size_t i = 1; i < t.size(); ++i)
    EXPECT_GE(t[i].t_ns - t[0].t_ns, std::int64_t(i) * pulse_ns - 10'000'000) << "transition " << i;
  rig.output->on_event(event("stooped", AlertChange::Cleared));
  const auto deadline = std::chrono::steady_clock::now() + test::scaled(2s);
  while (rig.high() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(1ms);
  EXPECT_FALSE(rig.high());
  const std::size_t after_clear = rig.fake->transitions().size();
  std::this_thread::sleep_for(3 * pulse);
  EXPECT_EQ(rig.fake->transitions().size(), after_clear) << "no pulses once the alert cleared";
}

TEST(AlertOutput, SilentModeNeverTouchesTheLine) {
  Rig rig({.mode = AlertSignalMode::Steady, .silent = true});
  rig.output->on_event(event("stooped", AlertChange::Raised));
  std::this_thread::sleep_for(50ms);
  rig.output->on_event(event("stooped", AlertChange::Cleared));
  rig.output->on_event(event("stooped", AlertChange::Raised));
  std::this_thread::sleep_for(50ms);
  EXPECT_TRUE(rig.fake->transitions().empty());
  EXPECT_EQ(rig.output->stats().signalled, 0u);
  EXPECT_TRUE(rig.output->silent());
  // Out of silent mode (a reload), what is still raised is signalled …
  rig.output->set_silent(false);
  auto t = rig.wait_for(1);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_TRUE(t[0].high);
  // … and back into it, the line goes inactive at once.
  rig.output->set_silent(true);
  t = rig.wait_for(2);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_FALSE(t[1].high);
}

TEST(AlertOutput, PulseModeSilentNeverTouchesTheLineEither) {
  Rig rig({.mode = AlertSignalMode::Pulse, .pulse = 20ms, .silent = true});
  rig.output->on_event(event("stooped", AlertChange::Raised));
  std::this_thread::sleep_for(100ms);
  rig.output->stop();
  EXPECT_TRUE(rig.fake->transitions().empty());
}

TEST(AlertOutput, StopDrivesTheLineInactiveWhileAnAlertIsRaised) {
  Rig rig({.mode = AlertSignalMode::Steady});
  rig.output->on_event(event("stooped", AlertChange::Raised));
  ASSERT_EQ(rig.wait_for(1).size(), 1u);
  rig.output->stop();
  auto t = rig.fake->transitions();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_FALSE(t[1].high);
  rig.output->stop();  // idempotent
  rig.output.reset();
  EXPECT_EQ(rig.fake->transitions().size(), 2u);
}

TEST(AlertOutput, DestroyingTheOutputReleasesTheLineInactive) {
  Rig rig({.mode = AlertSignalMode::Pulse, .pulse = 20ms});
  rig.output->on_event(event("stooped", AlertChange::Raised));
  ASSERT_GE(rig.wait_for(1).size(), 1u);
  rig.output.reset();  // RAII: as at SIGTERM, whatever phase the pulse was in
  EXPECT_FALSE(rig.high());
}

TEST(AlertOutput, WriteErrorsAreCountedAndTheNextChangeTriesAgain) {
  Rig rig({.mode = AlertSignalMode::Steady});
  rig.fail->store(true);
  rig.output->on_event(event("stooped", AlertChange::Raised));
  const auto deadline = std::chrono::steady_clock::now() + test::scaled(2s);
  while (rig.output->stats().write_errors == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(1ms);
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(rig.output->stats().write_errors, 1u) << "one failed write, not a retry loop";
  rig.fail->store(false);
  rig.output->on_event(event("stooped", AlertChange::Cleared));
  std::this_thread::sleep_for(20ms);
  rig.output->on_event(event("other", AlertChange::Raised));
  std::this_thread::sleep_for(20ms);
  rig.output->on_event(event("other", AlertChange::Cleared));
  auto t = rig.wait_for(2);
  EXPECT_EQ(rig.output->stats().write_errors, 1u);
  EXPECT_FALSE(rig.high());
}

TEST(AlertOutputKeys, ModeParsedOnceIntoAnEnum) {
  for (auto [text, mode] : {std::pair{"steady", AlertSignalMode::Steady}, {"pulse", AlertSignalMode::Pulse}}) {
    auto c = parse_config(std::string("[alerts]\ngpio_mode = \"") + text + "\"\n", "s.toml");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->alerts.gpio_mode, mode) << text;
    EXPECT_EQ(to_string(mode), text);
  }
}

TEST(AlertOutputKeys, DefaultsAndValuesReachTheConfig) {
  auto d = parse_config("", "s.toml");
  ASSERT_TRUE(d);
  EXPECT_FALSE(d->alerts.silent);
  EXPECT_EQ(d->alerts.gpio_chip, "");
  EXPECT_EQ(d->alerts.gpio_mode, AlertSignalMode::Steady);
  EXPECT_EQ(d->alerts.pulse_ms, 500);
  auto c = parse_config("[alerts]\nsilent = true\ngpio_chip = \"gpiochip1\"\ngpio_line = 17\ngpio_active_low = true\n"
                        "gpio_mode = \"pulse\"\npulse_ms = 250\n",
                        "s.toml");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_TRUE(c->alerts.silent);
  EXPECT_EQ(c->alerts.gpio_chip, "gpiochip1");
  EXPECT_EQ(c->alerts.gpio_line, 17);
  EXPECT_TRUE(c->alerts.gpio_active_low);
  EXPECT_EQ(c->alerts.gpio_mode, AlertSignalMode::Pulse);
  EXPECT_EQ(c->alerts.pulse_ms, 250);
}

TEST(AlertOutputKeys, BadValuesNameKeyAndLine) {
  auto mode = parse_config("[alerts]\n\ngpio_mode = \"blink\"\n", "s.toml");
  ASSERT_FALSE(mode);
  EXPECT_EQ(mode.error().message, "s.toml:3: alerts.gpio_mode: \"blink\" is not one of: steady, pulse");
  auto pulse = parse_config("[alerts]\npulse_ms = 5\n", "s.toml");
  ASSERT_FALSE(pulse);
  EXPECT_EQ(pulse.error().message, "s.toml:2: alerts.pulse_ms: 5 is out of range [20, 60000]");
  auto line = parse_config("[alerts]\ngpio_line = -1\n", "s.toml");
  ASSERT_FALSE(line);
  EXPECT_EQ(line.error().message, "s.toml:2: alerts.gpio_line: -1 is out of range [0, 1023]");
  auto silent = parse_config("[alerts]\nsilent = \"yes\"\n", "s.toml");
  ASSERT_FALSE(silent);
  EXPECT_EQ(silent.error().message, "s.toml:2: alerts.silent: expected true or false, got string");
}

TEST(AlertOutputKeys, SilentIsReloadableTheLineIsNot) {
  auto a = parse_config("", "s.toml");
  auto b = parse_config("[alerts]\nsilent = true\ngpio_chip = \"gpiochip0\"\n", "s.toml");
  ASSERT_TRUE(a && b);
  const auto changed = changed_keys(*a, *b);
  EXPECT_EQ(changed, (std::vector<std::string>{"alerts.silent", "alerts.gpio_chip"}));
  EXPECT_TRUE(reloadable_key("alerts.silent"));
  EXPECT_FALSE(reloadable_key("alerts.gpio_chip"));
  EXPECT_FALSE(reloadable_key("alerts.gpio_mode"));
}

TEST(SilentAlertLines, SaySilentAndValidate) {
  AlertEvent e = event("stooped", AlertChange::Raised);
  e.seq = 300;
  e.t_ns = 10'000'000'000;
  e.held_s = 10.0;
  e.inclination_deg = 64.2;
  const auto loud = nlohmann::json::parse(encode_alert(e));
  EXPECT_FALSE(loud.contains("silent")) << "optional: absent unless silent";
  const std::string line = encode_alert(e, {}, true);
  EXPECT_EQ(nlohmann::json::parse(line).at("silent"), true);
  test::TempDir dir;
  test::write_file(dir / "a.ndjson", line + "\n" + encode_alert(e) + "\n");
  EXPECT_EQ(test::validate_ndjson(dir / "a.ndjson"), "");
}

}  // namespace
}  // namespace spinewatch
