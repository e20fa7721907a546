// Our libgpiod trigger code against a real GPIO character device: gpio-sim
// (built out of tree, configured through configfs by the guest's /init).
// Line 0 is the master's output, line 1 the slave's input.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "guest_env.hpp"
#include "spinewatch/sync/gpiod_trigger_line.hpp"
#include "spinewatch/sync/trigger_master.hpp"
#include "spinewatch/sync/trigger_slave.hpp"

namespace spinewatch::kernel_test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr unsigned kMasterLine = 0;
constexpr unsigned kSlaveLine = 1;

// gpio-sim's view of a line: /sys/devices/platform/gpio-sim.N/gpiochipM/sim_gpioK/{value,pull}.
fs::path sim_attribute(unsigned line, const char* name) {
  return fs::path(env_or_empty("SW_GPIO_SYSFS")) / ("sim_gpio" + std::to_string(line)) / name;
}

int sim_value(unsigned line) {
  std::ifstream in(sim_attribute(line, "value"));
  int v = -1;
  in >> v;
  return v;
}

void sim_pull(unsigned line, const char* pull) {
  std::ofstream out(sim_attribute(line, "pull"));
  out << pull;
  out.flush();
  ASSERT_TRUE(out.good()) << "writing " << pull << " to " << sim_attribute(line, "pull");
}

TEST(Gpio, MasterDrivesSimLine) {
  SW_REQUIRE_ENV("SW_GPIO_SKIP", "SW_GPIO_CHIP", "SW_GPIO_SYSFS");
  auto line = sync::open_gpiod_output(env_or_empty("SW_GPIO_CHIP"), kMasterLine, "kernel-test");
  ASSERT_TRUE(line.ok()) << line.error().message;
  EXPECT_EQ(sim_value(kMasterLine), 0) << "requested as an output driven low";
  ASSERT_TRUE((*line)->set(true).ok());
  EXPECT_EQ(sim_value(kMasterLine), 1);
  ASSERT_TRUE((*line)->set(false).ok());
  EXPECT_EQ(sim_value(kMasterLine), 0);

  // 10 Hz with 30 ms pulses: slow enough for an emulated CPU to sample every pulse.
  std::mutex mutex;
  std::vector<std::int64_t> edges;
  int seen_rising = 0;
  {
    // The default SCHED_FIFO priority: the guest runs us as root, so the kernel grants it.
    sync::TriggerMaster master(**line, {.fps = 10.0, .pulse_us = 30'000},
                               [&](std::int64_t t) {
                                 std::lock_guard lock(mutex);
                                 edges.push_back(t);
                               });
    int last = 0;
    const auto end = std::chrono::steady_clock::now() + 1050ms;
    while (std::chrono::steady_clock::now() < end) {
      const int v = sim_value(kMasterLine);
      ASSERT_TRUE(v == 0 || v == 1);
      if (v == 1 && last == 0) ++seen_rising;
      last = v;
      std::this_thread::sleep_for(2ms);
    }
    master.stop();
    EXPECT_TRUE(master.realtime());
    EXPECT_EQ(master.line_errors(), 0u);
  }
  EXPECT_EQ(sim_value(kMasterLine), 0) << "the master leaves the line low";
  std::lock_guard lock(mutex);
  EXPECT_GE(edges.size(), 8u);
  EXPECT_LE(edges.size(), 12u);
  // Every pulse the master made was visible on the line (a slow sampler may
  // see the first one twice as late, never more than the master made).
  EXPECT_LE(seen_rising, static_cast<int>(edges.size()));
  EXPECT_GE(seen_rising, static_cast<int>(edges.size()) - 2);
  for (std::size_t i = 1; i < edges.size(); ++i) {
    // Absolute deadlines: the spacing stays one period on average.
    EXPECT_GT(edges[i], edges[i - 1]);
  }
  if (edges.size() >= 2) {
    const double mean = static_cast<double>(edges.back() - edges.front()) / static_cast<double>(edges.size() - 1);
    EXPECT_NEAR(mean, 100e6, 10e6);
  }
}

TEST(Gpio, SlaveTimestampsPulls) {
  SW_REQUIRE_ENV("SW_GPIO_SKIP", "SW_GPIO_CHIP", "SW_GPIO_SYSFS");
  sim_pull(kSlaveLine, "pull-down");
  auto line = sync::open_gpiod_input(env_or_empty("SW_GPIO_CHIP"), kSlaveLine, "kernel-test");
  ASSERT_TRUE(line.ok()) << line.error().message;
  std::mutex mutex;
  std::vector<std::int64_t> edges;
  sync::TriggerSlave slave(**line, [&](std::int64_t t) {
    std::lock_guard lock(mutex);
    edges.push_back(t);
  });
  auto edge_count = [&] {
    std::lock_guard lock(mutex);
    return edges.size();
  };
  constexpr int kPulses = 5;
  for (int k = 0; k < kPulses; ++k) {
    SCOPED_TRACE("pulse " + std::to_string(k));
    const std::int64_t before = monotonic_now_ns();
    sim_pull(kSlaveLine, "pull-up");
    const std::int64_t after = monotonic_now_ns();
    const auto deadline = std::chrono::steady_clock::now() + 2s;
    while (edge_count() < static_cast<std::size_t>(k + 1) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(1ms);
    }
    ASSERT_EQ(edge_count(), static_cast<std::size_t>(k + 1)) << "no rising edge reported";
    {
      std::lock_guard lock(mutex);
      // The kernel stamps the edge in its interrupt handler, during the write:
      // on the frames' clock (CLOCK_MONOTONIC), between our two readings.
      EXPECT_GE(edges[k], before);
      EXPECT_LE(edges[k], after);
    }
    sim_pull(kSlaveLine, "pull-down");  // a falling edge: not reported
    std::this_thread::sleep_for(20ms);
  }
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(edge_count(), static_cast<std::size_t>(kPulses)) << "falling edges must not be reported";
  slave.stop();
  EXPECT_EQ(slave.read_errors(), 0u);
}

}  // namespace
}  // namespace spinewatch::kernel_test
