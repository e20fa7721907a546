// The built firmware (.elf) in simavr: pulse timing from the real Timer1
// compare hardware model, the UART protocol on the fly, EEPROM at boot.
// Tolerances are one timer tick (8 cycles = 0.5 us) as commanded.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "sim_controller.hpp"

extern "C" {
#include "trig_eeprom_image.h"
}

namespace spinewatch::firmware_test {
namespace {

constexpr double kTick = static_cast<double>(kCyclesPerTick);

double period_cycles(double hz) { return static_cast<double>(kCpuHz) / hz; }

// Smallest and largest delay, in cycles, from each pulse's rising edge to
// the matching pulse's rising edge on another pin (same number of pulses).
std::pair<std::int64_t, std::int64_t> rise_lag(const std::vector<Pulse>& from, const std::vector<Pulse>& to) {
  std::int64_t lo = INT64_MAX, hi = INT64_MIN;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const auto lag = static_cast<std::int64_t>(to[i].rise) - static_cast<std::int64_t>(from[i].rise);
    lo = std::min(lo, lag);
    hi = std::max(hi, lag);
  }
  return {lo, hi};
}

std::vector<double> periods(const std::vector<Pulse>& pulses) {
  std::vector<double> out;
  for (std::size_t i = 1; i < pulses.size(); ++i) out.push_back(static_cast<double>(pulses[i].rise - pulses[i - 1].rise));
  return out;
}

double max_abs_error(const std::vector<double>& values, double expected) {
  double worst = 0;
  for (double v : values) worst = std::max(worst, std::abs(v - expected));
  return worst;
}

std::string ok(SimController& sim, const std::string& line) {
  const auto reply = sim.command(line);
  EXPECT_TRUE(reply.has_value()) << line << ": no reply";
  if (!reply) return {};
  EXPECT_EQ(reply->rfind("OK", 0), 0u) << line << " -> " << *reply;
  return *reply;
}

struct RateCase {
  double hz;
  int width_us;
};

class TriggerRate : public ::testing::TestWithParam<RateCase> {};

TEST_P(TriggerRate, PeriodAndWidthWithinOneTick) {
  const auto [hz, width_us] = GetParam();
  const auto wall0 = std::chrono::steady_clock::now();
  SimController sim;
  sim.run_us(5'000);
  ok(sim, "CONFIG " + std::to_string(static_cast<int>(hz)) + " " + std::to_string(width_us) + " 0 0");
  // The new timing holds from the next period boundary (within one 30 Hz period).
  const std::uint64_t from = sim.cycle() + static_cast<std::uint64_t>(period_cycles(30.0)) + 1;
  const int want_periods = hz < 2 ? 2 : 8;
  sim.run_until_cycle(from + static_cast<std::uint64_t>(period_cycles(hz) * (want_periods + 1)));
  const auto a = sim.pulses(Pin::CameraA, from);
  const auto b = sim.pulses(Pin::CameraB, from);
  ASSERT_GE(a.size(), static_cast<std::size_t>(want_periods)) << "pulses at " << hz << " Hz";
  ASSERT_GE(b.size(), static_cast<std::size_t>(want_periods));
  const auto p = periods(a);
  const double period_err = max_abs_error(p, period_cycles(hz));
  std::vector<double> widths;
  for (const auto& pulse : a) widths.push_back(static_cast<double>(pulse.width()));
  for (const auto& pulse : b) widths.push_back(static_cast<double>(pulse.width()));
  const double width_err = max_abs_error(widths, width_us * static_cast<double>(kCyclesPerUs));
  EXPECT_LE(period_err, kTick) << hz << " Hz";
  EXPECT_LE(width_err, kTick) << hz << " Hz, " << width_us << " us";
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("[ figures ] %.0f Hz width %d us: %zu periods, max period error %.1f cycles = %.2f ticks = %.3f us; "
              "max width error %.1f cycles = %.2f ticks = %.3f us; simulated %.3f s in %.3f s wall\n",
              hz, width_us, p.size(), period_err, period_err / kTick, period_err / kCyclesPerUs, width_err,
              width_err / kTick, width_err / kCyclesPerUs, static_cast<double>(sim.cycle()) / kCpuHz, wall);
}

INSTANTIATE_TEST_SUITE_P(Rates, TriggerRate,
                         ::testing::Values(RateCase{1, 1000}, RateCase{1, 600000}, RateCase{30, 1000},
                                           RateCase{60, 20}, RateCase{120, 1000}, RateCase{120, 8233}),
                         [](const auto& info) {
                           return std::to_string(static_cast<int>(info.param.hz)) + "Hz_" +
                                  std::to_string(info.param.width_us) + "us";
                         });

TEST(TriggerFirmware, BootsWithDefaultsWhenEepromIsBlankOrCorrupt) {
  std::vector<std::uint8_t> corrupt(64);
  for (std::size_t i = 0; i < corrupt.size(); ++i) corrupt[i] = static_cast<std::uint8_t>(i * 37 + 5);
  corrupt[0] = TRIG_EEPROM_MAGIC;  // right magic, wrong everything else
  corrupt[1] = TRIG_EEPROM_LAYOUT;
  const std::vector<const std::vector<std::uint8_t>*> images = {nullptr, &corrupt};  // blank (0xFF), damaged
  for (const auto* image : images) {
    SimController sim(image);
    sim.run_us(2'000);
    const std::string status = ok(sim, "STATUS");
    EXPECT_NE(status.find("rate=30.000 width=1000 delay_a=0 delay_b=0 running=1"), std::string::npos) << status;
    sim.run_us(100'000);
    EXPECT_GE(sim.pulses(Pin::CameraA).size(), 3u) << "defaults run at power-on";
  }
}

TEST(TriggerFirmware, BootsFromAnImageTheHostEncoded) {
  // The host CRC (firmware/common) and avr-libc's _crc16_update on the device agree.
  trig_state st{};
  st.settings.rate_mhz = 60000;
  st.settings.width_us = 500;
  st.settings.delay_us[TRIG_CH_A] = 0;
  st.settings.delay_us[TRIG_CH_B] = 100;
  st.running = 0;
  std::vector<std::uint8_t> image(TRIG_EEPROM_SIZE);
  trig_eeprom_encode(&st, image.data());
  SimController sim(&image);
  sim.run_us(50'000);
  EXPECT_NE(ok(sim, "STATUS").find("rate=60.000 width=500 delay_a=0 delay_b=100 running=0"), std::string::npos);
  EXPECT_TRUE(sim.pulses(Pin::CameraA).empty()) << "saved as stopped";
}

TEST(TriggerFirmware, SavedSettingsSurviveAReset) {
  SimController sim;
  sim.run_us(2'000);
  ok(sim, "CONFIG 120 200 0 50");
  ok(sim, "STOP");
  ok(sim, "SAVE");
  trig_state decoded{};
  ASSERT_EQ(trig_eeprom_decode(sim.eeprom(TRIG_EEPROM_SIZE).data(), &decoded), 1);
  EXPECT_EQ(decoded.settings.rate_mhz, 120000u);
  EXPECT_EQ(decoded.settings.delay_us[TRIG_CH_B], 50u);
  sim.reset();
  sim.run_us(2'000);
  EXPECT_NE(ok(sim, "STATUS").find("rate=120.000 width=200 delay_a=0 delay_b=50 running=0"), std::string::npos);
  ok(sim, "DEFAULTS");
  EXPECT_NE(ok(sim, "STATUS").find("rate=30.000 width=1000 delay_a=0 delay_b=0"), std::string::npos);
}

TEST(TriggerFirmware, CamerasCoincideAtZeroDelayAndSyncFollowsCameraA) {
  SimController sim;
  sim.run_us(300'000);
  const auto a = sim.pulses(Pin::CameraA);
  const auto b = sim.pulses(Pin::CameraB);
  const auto s = sim.pulses(Pin::Sync);
  ASSERT_GE(a.size(), 8u);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), s.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].rise, b[i].rise) << "pulse " << i;
    EXPECT_EQ(a[i].fall, b[i].fall) << "pulse " << i;
  }
  const auto [lag_min, lag_max] = rise_lag(a, s);
  // The sync line is set by the compare ISR: a few microseconds late, never early.
  EXPECT_GT(lag_min, 0);
  EXPECT_LT(lag_max, static_cast<std::int64_t>(10 * kCyclesPerUs));
  std::printf("[ figures ] sync line after camera A rising edge: %lld..%lld cycles (%.2f..%.2f us), jitter %lld cycles\n",
              static_cast<long long>(lag_min), static_cast<long long>(lag_max), lag_min / 16.0, lag_max / 16.0,
              static_cast<long long>(lag_max - lag_min));
}

TEST(TriggerFirmware, CameraBFollowsAtTheCommandedDelay) {
  SimController sim;
  sim.run_us(1'000);
  ok(sim, "CONFIG 60 500 100 350");
  const std::uint64_t from = sim.cycle() + static_cast<std::uint64_t>(period_cycles(30.0));
  sim.run_us(200'000);
  const auto a = sim.pulses(Pin::CameraA, from);
  const auto b = sim.pulses(Pin::CameraB, from);
  ASSERT_GE(a.size(), 8u);
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    const double skew = static_cast<double>(b[i].rise) - static_cast<double>(a[i].rise);
    EXPECT_NEAR(skew, 250.0 * kCyclesPerUs, kTick) << "pulse " << i;
    EXPECT_NEAR(static_cast<double>(b[i].width()), 500.0 * kCyclesPerUs, kTick);
  }
}

TEST(TriggerFirmware, RateChangeWhileRunningTakesEffectNextPeriodWithoutARunt) {
  for (const std::uint64_t at_us : {100'900u, 110'000u}) {  // during a pulse / in the gap between pulses
    SimController sim;
    sim.run_us(at_us);
    const std::uint64_t sent = sim.cycle();
    ok(sim, "RATE 60");
    const std::uint64_t replied = sim.cycle();
    sim.run_us(150'000);
    const auto a = sim.pulses(Pin::CameraA);
    ASSERT_GE(a.size(), 10u);
    // Periods (rise to rise) that end before the command are 30 Hz; those
    // that start after it was handled are 60 Hz; the one it arrived in may
    // be either (60 Hz when its pulse had not ended yet), never anything else.
    int switches = 0;
    for (std::size_t i = 1; i < a.size(); ++i) {
      const double p = static_cast<double>(a[i].rise - a[i - 1].rise);
      const bool old_rate = std::abs(p - period_cycles(30)) <= kTick;
      const bool new_rate = std::abs(p - period_cycles(60)) <= kTick;
      if (a[i].rise <= sent) {
        EXPECT_TRUE(old_rate) << "period " << i << " before the command: " << p;
      }
      if (a[i - 1].rise >= replied) {
        EXPECT_TRUE(new_rate) << "period " << i << " after the command: " << p;
      }
      EXPECT_TRUE(old_rate || new_rate) << "period " << i << ": " << p << " cycles";
      if (i >= 2) switches += (std::abs(static_cast<double>(a[i - 1].rise - a[i - 2].rise) - p) > kTick) ? 1 : 0;
    }
    EXPECT_EQ(switches, 1);
    for (const auto& pulse : a) EXPECT_NEAR(static_cast<double>(pulse.width()), 1000.0 * kCyclesPerUs, kTick);
    const auto b = sim.pulses(Pin::CameraB);
    ASSERT_EQ(b.size(), a.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].rise, b[i].rise);
  }
}

TEST(TriggerFirmware, MalformedCommandsGetErrAndPulsesKeepRunning) {
  SimController sim;
  sim.run_us(1'000);
  ok(sim, "RATE 60");
  const std::uint64_t from = sim.cycle() + static_cast<std::uint64_t>(period_cycles(30.0));
  const std::vector<std::string> bad = {"",         "garbage !!", std::string(60, 'x'), "RATE 500", "RATE abc",
                                        "WIDTH 5",  "\x01\x02\x7f", "DELAY C 10",          "START now", "RATE 60 60",
                                        std::string(300, '9')};
  for (const auto& line : bad) {
    const auto reply = sim.command(line);
    ASSERT_TRUE(reply.has_value()) << "no reply to a " << line.size() << "-byte line";
    EXPECT_EQ(reply->rfind("ERR ", 0), 0u) << line << " -> " << *reply;
  }
  EXPECT_EQ(*sim.command(std::string(60, 'x')), "ERR line too long");
  sim.run_us(100'000);
  EXPECT_NE(ok(sim, "STATUS").find("rate=60.000 width=1000"), std::string::npos);
  const auto a = sim.pulses(Pin::CameraA, from);
  ASSERT_GE(a.size(), 8u);
  // Pulses from start to end of the whole exchange, every period exact.
  EXPECT_LT(static_cast<double>(a.front().rise - from), period_cycles(60));
  EXPECT_LT(static_cast<double>(sim.cycle() - a.back().rise), period_cycles(60) + 1000.0 * kCyclesPerUs);
  EXPECT_LE(max_abs_error(periods(a), period_cycles(60)), kTick) << "a gap or glitch while bad lines arrived";
  // The sync line under UART load: its ISR may wait for the receive ISR.
  const auto sync = sim.pulses(Pin::Sync, from);
  ASSERT_EQ(sync.size(), a.size());
  const auto [lag_min, lag_max] = rise_lag(a, sync);
  EXPECT_GT(lag_min, 0);
  EXPECT_LT(lag_max, static_cast<std::int64_t>(15 * kCyclesPerUs));
  std::printf("[ figures ] sync line lag under UART input: %lld..%lld cycles (%.2f..%.2f us)\n",
              static_cast<long long>(lag_min), static_cast<long long>(lag_max), lag_min / 16.0, lag_max / 16.0);
}

TEST(TriggerFirmware, StopEndsAfterTheCurrentPulseAndStartResumes) {
  SimController sim;
  sim.run_us(100'500);
  ok(sim, "STOP");
  const std::uint64_t stopped = sim.cycle();
  sim.run_us(100'000);
  const auto before = sim.pulses(Pin::CameraA);
  ASSERT_FALSE(before.empty());
  EXPECT_LT(before.back().rise, stopped + static_cast<std::uint64_t>(period_cycles(30)));
  for (const auto& pulse : before) EXPECT_NEAR(static_cast<double>(pulse.width()), 16000.0, kTick);
  EXPECT_EQ(sim.edges(Pin::CameraA).back().high, false);
  EXPECT_NE(ok(sim, "STATUS").find("running=0"), std::string::npos);

  const std::uint64_t idle_from = sim.cycle();
  sim.run_us(50'000);
  EXPECT_TRUE(sim.pulses(Pin::CameraA, idle_from).empty());
  const std::uint64_t sent = sim.cycle();
  ok(sim, "START");
  sim.run_us(100'000);
  const auto after = sim.pulses(Pin::CameraA, sent);
  ASSERT_GE(after.size(), 3u);
  // "START\n" takes 6 byte times (521 us) to arrive and one more to be
  // received; the first pulse follows 100 us after the line is handled.
  EXPECT_LT(after.front().rise - sent, 1000u * kCyclesPerUs) << "first pulse soon after START";
  EXPECT_LE(max_abs_error(periods(after), period_cycles(30)), kTick);
}

TEST(TriggerFirmware, CounterEqualsThePulsesSeen) {
  SimController sim;
  sim.run_us(50'000);
  ok(sim, "RATE 120");
  sim.run_us(60'000);
  ok(sim, "CONFIG 1 1000 0 0");
  sim.run_us(1'100'000);
  ok(sim, "RATE 90");
  sim.run_us(50'000);
  ok(sim, "STOP");
  sim.run_us(30'000);
  const std::string status = ok(sim, "STATUS");
  const std::size_t counted = sim.pulses(Pin::CameraA).size();
  EXPECT_NE(status.find(" count=" + std::to_string(counted) + " "), std::string::npos)
      << status << " vs " << counted << " pulses seen";
  const auto at = status.find("uptime_ms=");
  ASSERT_NE(at, std::string::npos);
  // Sampled when STATUS was handled, before its ~90-byte reply went out (~8 ms).
  const double uptime_ms = std::atof(status.c_str() + at + 10);
  const double now_ms = static_cast<double>(sim.cycle()) / (kCpuHz / 1000);
  EXPECT_LE(uptime_ms, now_ms);
  EXPECT_GE(uptime_ms, now_ms - 10);
}

}  // namespace
}  // namespace spinewatch::firmware_test
