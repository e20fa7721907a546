#include <algorithm>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <spdlog/spdlog.h>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "test_support.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "spinewatch/sync/fake_trigger_line.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

CameraPairOptions fake_options() {
  CameraPairOptions o;
  o.frontal.path = "/dev/video-front";
  o.lateral.path = "/dev/video-side";
  o.frontal.fps = o.lateral.fps = 30.0;
  return o;
}

std::shared_ptr<FakeV4l2Device> fake_camera(const std::string& path, FakeV4l2Script script = {}) {
  script.path = path;
  script.paced = true;
  return std::make_shared<FakeV4l2Device>(script);
}

TEST(CameraPairSource, PairsTwoCamerasWithMatchingTimes) {
  auto front = fake_camera("/dev/video-front"), side = fake_camera("/dev/video-side");
  auto source = open_camera_pair_source(fake_options(), front, side);
  ASSERT_TRUE(source.ok()) << source.error().message;
  std::optional<std::int64_t> previous;
  for (int i = 0; i < 8; ++i) {
    auto pair = (*source)->next();
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->frontal.format().width, 320u);
    EXPECT_EQ(pair->lateral.bytes().size(), pair->lateral.format().frame_bytes());
    EXPECT_LE(std::llabs(pair->frontal.timestamp_ns() - pair->lateral.timestamp_ns()), 16'666'667);
    if (previous) {
      EXPECT_GT(pair->timestamp_ns, *previous);
    }
    previous = pair->timestamp_ns;
  }
  (*source)->stop();
  EXPECT_FALSE((*source)->next());
  EXPECT_GE((*source)->stats().frames, 16u);
  EXPECT_EQ((*source)->describe(), "v4l2 /dev/video-front /dev/video-side");
  // Pairs hold copies, so every mmap buffer went back to the driver.
  source = Error{""};
  EXPECT_EQ(front->open_fds(), 0);
  EXPECT_EQ(side->open_fds(), 0);
}

TEST(CameraPairSource, LostFramesAreCounted) {
  FakeV4l2Script skipping;
  skipping.skipped_sequences = {3, 4, 5};
  auto source = open_camera_pair_source(fake_options(), fake_camera("/dev/video-front", skipping),
                                        fake_camera("/dev/video-side"));
  ASSERT_TRUE(source.ok()) << source.error().message;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE((*source)->next());
  (*source)->stop();
  EXPECT_GE((*source)->stats().frames_lost, 3u);
}

TEST(CameraPairSource, AMissingCameraIsAnErrorNamingIt) {
  spdlog::set_level(spdlog::level::off);
  auto o = fake_options();
  o.lateral.path = "/dev/video-absent";
  auto source = open_camera_pair_source(o, fake_camera("/dev/video-front"), fake_camera("/dev/video-side"));
  spdlog::set_level(spdlog::level::info);
  ASSERT_FALSE(source.ok());
  EXPECT_NE(source.error().message.find("/dev/video-absent"), std::string::npos) << source.error().message;
}

TEST(CameraPairSource, StopWakesABlockedNext) {
  FakeV4l2Script stalls;
  stalls.stall_after = 2;
  auto source = open_camera_pair_source(fake_options(), fake_camera("/dev/video-front", stalls),
                                        fake_camera("/dev/video-side", stalls));
  ASSERT_TRUE(source.ok()) << source.error().message;
  std::thread stopper([&] {
    std::this_thread::sleep_for(300ms);
    (*source)->stop();
  });
  const auto t0 = std::chrono::steady_clock::now();
  while ((*source)->next()) {
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
  stopper.join();
}

// A camera unplugged mid-stream: one camera_lost marker where the gap
// begins, then pairs again from the same source (no restart of anything
// above the camera), and the counters say what happened.
TEST(CameraPairSource, AnUnpluggedCameraIsMarkedOnceAndPairsResume) {
  spdlog::set_level(spdlog::level::off);
  FakeV4l2Script unplugging;
  unplugging.unplug_after = 30;  // and again 30 frames after each return
  unplugging.reopen_failures = 1;
  auto o = fake_options();
  o.lateral.retry_initial = 20ms;
  auto side = fake_camera("/dev/video-side", unplugging);
  auto source = open_camera_pair_source(o, fake_camera("/dev/video-front"), side);
  ASSERT_TRUE(source.ok()) << source.error().message;
  int pairs_before = 0, markers = 0, pairs_after = 0;
  std::optional<std::int64_t> previous;  // the last pair's time
  const auto deadline = std::chrono::steady_clock::now() + test::scaled(20s);
  while (pairs_after < 8 && std::chrono::steady_clock::now() < deadline) {
    auto pair = (*source)->next();
    ASSERT_TRUE(pair);
    if (pair->camera_lost) {
      ++markers;
      EXPECT_TRUE(pair->frontal.bytes().empty());
      // The gap begins after the last pair: the stream's time never goes back.
      EXPECT_EQ(pair->timestamp_ns, previous.value_or(-1));
      continue;
    }
    ++(markers == 0 ? pairs_before : pairs_after);
    EXPECT_GT(pair->timestamp_ns, previous.value_or(0));
    previous = pair->timestamp_ns;
  }
  const SourceStats stats = (*source)->stats();
  (*source)->stop();
  spdlog::set_level(spdlog::level::info);
  EXPECT_GE(pairs_before, 3);
  EXPECT_EQ(markers, 1);
  EXPECT_EQ(pairs_after, 8);
  EXPECT_EQ(stats.camera[1].losses, 1u);
  EXPECT_EQ(stats.camera[1].restarts, 1u);
  EXPECT_EQ(stats.camera[0].losses, 0u);
  EXPECT_GT(stats.frames_lost, 0u);  // the frontal frames that had no partner meanwhile
}

// Edges the trigger reported, as the test saw them.
struct EdgeLog {
  std::mutex mutex;
  std::vector<std::int64_t> edges;
  bool contains(std::int64_t t) {
    std::lock_guard lock(mutex);
    return std::find(edges.begin(), edges.end(), t) != edges.end();
  }
};

TEST(CameraPairSource, MasterModePairsFramesToTheEdgesItDrives) {
  auto o = fake_options();
  o.trigger.mode = sync::TriggerMode::Master;
  EdgeLog log;
  sync::FakeTriggerLine* line = nullptr;
  TriggerFactory factory = [&](sync::TriggerSource::EdgeCallback on_edge) -> Result<std::unique_ptr<sync::TriggerSource>> {
    auto fake = std::make_unique<sync::FakeTriggerLine>();
    line = fake.get();
    return sync::TriggerSource::master(std::move(fake), {.fps = 30.0, .pulse_us = 1000, .realtime_priority = 0},
                                       [&log, on_edge](std::int64_t t) {
                                         {
                                           std::lock_guard lock(log.mutex);
                                           log.edges.push_back(t);
                                         }
                                         on_edge(t);
                                       });
  };
  auto source = open_camera_pair_source(o, fake_camera("/dev/video-front"), fake_camera("/dev/video-side"), factory);
  ASSERT_TRUE(source.ok()) << source.error().message;
  for (int i = 0; i < 6; ++i) {
    auto pair = (*source)->next();
    ASSERT_TRUE(pair);
    // Triggered: the pair carries its edge's time, and both frames lie
    // within half a period of it.
    EXPECT_TRUE(log.contains(pair->timestamp_ns)) << pair->timestamp_ns;
    EXPECT_LE(std::llabs(pair->frontal.timestamp_ns() - pair->timestamp_ns), 16'666'667);
    EXPECT_LE(std::llabs(pair->lateral.timestamp_ns() - pair->timestamp_ns), 16'666'667);
  }
  (*source)->stop();
  ASSERT_NE(line, nullptr);
  EXPECT_GE(line->transitions().size(), 12u);  // the master drove the line: high and low per edge
}

TEST(CameraPairSource, SlaveModeWithoutEdgesPairsNothingAndCountsTheFrames) {
  auto o = fake_options();
  o.trigger.mode = sync::TriggerMode::Slave;
  TriggerFactory factory = [](sync::TriggerSource::EdgeCallback on_edge) -> Result<std::unique_ptr<sync::TriggerSource>> {
    return sync::TriggerSource::slave(std::make_unique<sync::FakeTriggerLine>(), std::move(on_edge));
  };
  auto source = open_camera_pair_source(o, fake_camera("/dev/video-front"), fake_camera("/dev/video-side"), factory);
  ASSERT_TRUE(source.ok()) << source.error().message;
  // Long enough for more frames than the pairer holds while waiting (16).
  std::thread stopper([&] {
    std::this_thread::sleep_for(900ms);
    (*source)->stop();
  });
  EXPECT_FALSE((*source)->next());  // no edge, no pair: frames are never paired with each other
  stopper.join();
  EXPECT_GT((*source)->stats().frames, 0u);
  EXPECT_GT((*source)->stats().frames_lost, 0u);
}

TEST(CameraPairSource, TriggerModeFromTheConfig) {
  Config config;
  config.trigger.mode = sync::TriggerMode::Slave;
  config.trigger.frame_latency_us = 1500;
  const CameraPairOptions o = camera_pair_options(config);
  EXPECT_EQ(o.trigger.mode, sync::TriggerMode::Slave);
  EXPECT_EQ(o.trigger.chip, config.trigger.chip);
  EXPECT_EQ(o.frame_latency_ns, 1'500'000);
  // A GPIO chip that does not exist is an error naming it, not a hang.
  config.trigger.chip = "gpiochip-absent";
  auto source = open_camera_pair_source(camera_pair_options(config), fake_camera(config.cameras.frontal),
                                        fake_camera(config.cameras.lateral));
  ASSERT_FALSE(source.ok());
  EXPECT_NE(source.error().message.find("gpiochip-absent"), std::string::npos) << source.error().message;
}

// An unknown mode cannot reach the trigger any more: the configuration
// refuses it at load, naming key and line (Config.* in config_test.cpp).
TEST(TriggerSource, FreeRunHasNone) {
  auto none = sync::TriggerSource::open({.mode = sync::TriggerMode::FreeRun}, [](std::int64_t) {});
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none->get(), nullptr);
  EXPECT_EQ(sync::to_string(sync::TriggerMode::Slave), "slave");
}

}  // namespace
}  // namespace spinewatch
