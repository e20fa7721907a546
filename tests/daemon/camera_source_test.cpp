#include <gtest/gtest.h>

#include <spdlog/spdlog.h>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"

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

}  // namespace
}  // namespace spinewatch
