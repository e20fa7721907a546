#include <linux/videodev2.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

V4l2CameraOptions options_for(const FakeV4l2Script& script) {
  V4l2CameraOptions o;
  o.path = script.path;
  o.name = "test";
  o.retry_initial = 1ms;
  o.retry_max = 4ms;
  return o;
}

// The fake writes pattern(seq, x, y) into every byte of a row.
void expect_pattern(const Frame& frame, std::uint64_t driver_seq) {
  const auto& f = frame.format();
  const auto bytes = frame.bytes();
  ASSERT_EQ(bytes.size(), f.frame_bytes());
  for (std::uint32_t y : {0u, f.height / 2, f.height - 1}) {
    for (std::uint32_t x : {0u, 1u, f.min_bytesperline() - 1}) {
      ASSERT_EQ(bytes[std::size_t{y} * f.bytesperline + x], FakeV4l2Device::pattern(driver_seq, x, y))
          << "x " << x << " y " << y;
    }
  }
}

TEST(V4l2Camera, NegotiatesFormatRateAndControlsAndHonoursDriverStride) {
  FakeV4l2Script script;
  script.bytesperline_align = 256;  // 320 × 2 = 640 → 768
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.exposure_us = 8000;
  options.gain = 5;
  options.fps = 25.0;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  EXPECT_EQ(camera.format(), (FrameFormat{PixelFormat::YUYV, 320, 240, 768}));
  EXPECT_DOUBLE_EQ(fake->frame_rate(), 25.0);
  EXPECT_DOUBLE_EQ(camera.fps(), 25.0);
  const auto controls = fake->controls();
  EXPECT_EQ(controls.at(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(controls.at(V4L2_CID_EXPOSURE_ABSOLUTE), 80);  // 100 µs units
  EXPECT_EQ(controls.at(V4L2_CID_GAIN), 5);
  for (std::uint64_t k = 0; k < 6; ++k) {
    auto frame = camera.next(1s);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->sequence(), k);
    expect_pattern(*frame, k);
    EXPECT_EQ(frame->bytes()[640], FakeV4l2Device::kPadding);  // the driver's padding is kept, not read as pixels
  }
}

TEST(V4l2Camera, LeavesExposureAndGainToTheDriverWhenAsked) {
  FakeV4l2Script script;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.exposure_us = 0;
  options.gain = -1;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  EXPECT_TRUE(fake->controls().empty());
}

TEST(V4l2Camera, MissingControlsAreWarningsNotFailures) {
  FakeV4l2Script script;
  script.missing_controls = {V4L2_CID_GAIN, V4L2_CID_EXPOSURE_ABSOLUTE};
  script.timeperframe = false;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.exposure_us = 5000;
  options.gain = 3;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  const auto controls = fake->controls();
  EXPECT_EQ(controls.count(V4L2_CID_GAIN), 0u);
  EXPECT_EQ(controls.count(V4L2_CID_EXPOSURE_AUTO), 1u);
  EXPECT_TRUE(camera.next(1s));
}

TEST(V4l2Camera, ClearErrorsForDevicesItCannotUse) {
  {
    FakeV4l2Script script;
    auto fake = std::make_shared<FakeV4l2Device>(script);
    auto options = options_for(script);
    options.path = "/dev/video-missing";
    auto status = V4l2Camera(options, fake).start();
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("cannot open /dev/video-missing"), std::string::npos) << status.error().message;
  }
  {
    FakeV4l2Script script;
    script.capabilities = V4L2_CAP_STREAMING;  // an output-only or metadata node
    auto fake = std::make_shared<FakeV4l2Device>(script);
    auto status = V4l2Camera(options_for(script), fake).start();
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("not a video capture device"), std::string::npos) << status.error().message;
    EXPECT_EQ(fake->open_fds(), 0);
  }
  {
    FakeV4l2Script script;
    script.formats = {PixelFormat::GREY};
    auto fake = std::make_shared<FakeV4l2Device>(script);
    auto status = V4l2Camera(options_for(script), fake).start();
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("offers GREY instead of YUYV"), std::string::npos) << status.error().message;
  }
  {
    FakeV4l2Script script;
    script.max_buffers = 1;
    auto fake = std::make_shared<FakeV4l2Device>(script);
    auto status = V4l2Camera(options_for(script), fake).start();
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("only 1 buffer"), std::string::npos) << status.error().message;
    EXPECT_EQ(fake->mapped_buffers(), 0);
  }
}

TEST(V4l2Camera, GreyFormatUsesOneBytePerPixel) {
  FakeV4l2Script script;
  script.bytesperline_align = 64;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.pixel_format = PixelFormat::GREY;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  EXPECT_EQ(camera.format(), (FrameFormat{PixelFormat::GREY, 320, 240, 320}));
  auto frame = camera.next(1s);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->luma().step, 1);
  expect_pattern(*frame, 0);
}

TEST(V4l2Camera, BufferReturnsToTheDriverOnlyWhenTheLastCopyIsReleased) {
  FakeV4l2Script script;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.buffers = 4;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  std::vector<Frame> held;
  for (int i = 0; i < 4; ++i) {
    auto f = camera.next(1s);
    ASSERT_TRUE(f);
    held.push_back(*f);
  }
  EXPECT_EQ(fake->queued_buffers(), 0);
  // Every buffer is out: no frame, and none is stolen from the consumer.
  EXPECT_FALSE(camera.next(30ms));
  Frame copy = held[0];
  held.erase(held.begin());
  EXPECT_EQ(fake->queued_buffers(), 0);
  expect_pattern(copy, 0);  // still intact
  copy = Frame();
  EXPECT_EQ(fake->queued_buffers(), 1);
  auto f = camera.next(1s);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->sequence(), 4u);
  expect_pattern(*f, 4);
}

TEST(V4l2Camera, ErrorFramesAndSequenceGapsAreCountedAsDrops) {
  FakeV4l2Script script;
  script.error_sequences = {2, 5};
  script.skipped_sequences = {7, 8};
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  std::vector<std::uint64_t> seqs;
  for (int i = 0; i < 8; ++i) {
    auto f = camera.next(1s);
    ASSERT_TRUE(f);
    seqs.push_back(f->sequence());
  }
  EXPECT_EQ(seqs, (std::vector<std::uint64_t>{0, 1, 3, 4, 6, 9, 10, 11}));
  const auto c = camera.counters();
  EXPECT_EQ(c.frames, 8u);
  EXPECT_EQ(c.dropped_error, 2u);
  EXPECT_EQ(c.dropped_gap, 2u);
  EXPECT_EQ(c.restarts, 0u);
}

TEST(V4l2Camera, UsesTheDriversMonotonicTimestamps) {
  FakeV4l2Script script;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  auto first = camera.next(1s);
  auto later = camera.next(1s);
  later = camera.next(1s);
  ASSERT_TRUE(first && later);
  // The fake stamps frame k at start + k/30 s (µs resolution, as V4L2 has).
  EXPECT_NEAR(static_cast<double>(later->timestamp_ns() - first->timestamp_ns()), 2e9 / 30.0, 1000.0);
  EXPECT_LE(first->timestamp_ns(), monotonic_now_ns());
}

TEST(V4l2Camera, FallsBackToDequeueTimeWithoutAMonotonicStamp) {
  FakeV4l2Script script;
  script.timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  const std::int64_t before = monotonic_now_ns();
  auto f = camera.next(1s);
  ASSERT_TRUE(f);
  EXPECT_GE(f->timestamp_ns(), before);
  EXPECT_LE(f->timestamp_ns(), monotonic_now_ns());
}

TEST(V4l2Camera, RecoversFromDeviceLossWithoutRepeatingSequenceNumbers) {
  FakeV4l2Script script;
  script.unplug_after = 5;
  script.reopen_failures = 3;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  std::vector<std::uint64_t> seqs;
  Frame held;
  for (int i = 0; i < 12; ++i) {
    auto f = camera.next(2s);
    ASSERT_TRUE(f) << "frame " << i;
    if (i == 3) held = *f;  // a frame that outlives its stream
    seqs.push_back(f->sequence());
  }
  for (std::size_t i = 1; i < seqs.size(); ++i) EXPECT_GT(seqs[i], seqs[i - 1]);
  EXPECT_EQ(camera.counters().restarts, 2u);  // unplugged again 5 frames after the first return
  EXPECT_EQ(fake->stream_starts(), 3u);
  expect_pattern(held, 3);
}

TEST(V4l2Camera, PollErrorRestartsTheStream) {
  FakeV4l2Script script;
  script.pollerr_after = 3;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(camera.next(2s)) << i;
  EXPECT_EQ(camera.counters().restarts, 1u);
  EXPECT_EQ(fake->open_fds(), 1);
}

TEST(V4l2Camera, WatchdogReportsACameraThatStopsDelivering) {
  FakeV4l2Script script;
  script.stall_after = 3;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.watchdog_s = 0.05;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(camera.next(1s));
  EXPECT_FALSE(camera.stalled());
  EXPECT_FALSE(camera.next(200ms));
  EXPECT_TRUE(camera.stalled());
  EXPECT_FALSE(camera.next(100ms));
  EXPECT_EQ(camera.counters().stalls, 1u);  // reported once per stall
}

TEST(V4l2Camera, StopWakesABlockedNext) {
  FakeV4l2Script script;
  script.stall_after = 1;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  ASSERT_TRUE(camera.next(1s));
  std::thread stopper([&] {
    std::this_thread::sleep_for(20ms);
    camera.stop();
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(camera.next(10s));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  stopper.join();
  EXPECT_FALSE(camera.next(1s));
}

TEST(V4l2Camera, NegativeTimeoutWaitsForAFrameOrStop) {
  FakeV4l2Script script;
  script.paced = true;  // frames at their real times: the wait is real
  auto fake = std::make_shared<FakeV4l2Device>(script);
  auto options = options_for(script);
  options.fps = 100.0;
  V4l2Camera camera(options, fake);
  ASSERT_TRUE(camera.start().ok());
  for (std::uint64_t k = 0; k < 3; ++k) {
    auto f = camera.next(-1ms);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->sequence(), k);
  }
}

TEST(V4l2Camera, ReleasesEveryFdAndMappingEvenWhenFramesOutliveIt) {
  FakeV4l2Script script;
  auto fake = std::make_shared<FakeV4l2Device>(script);
  Frame survivor;
  {
    V4l2Camera camera(options_for(script), fake);
    ASSERT_TRUE(camera.start().ok());
    EXPECT_EQ(fake->mapped_buffers(), 4);
    survivor = *camera.next(1s);
    ASSERT_TRUE(camera.next(1s));
  }
  EXPECT_EQ(fake->open_fds(), 0);
  EXPECT_EQ(fake->mapped_buffers(), 4);  // the session lives while a frame does
  expect_pattern(survivor, 0);
  survivor = Frame();
  EXPECT_EQ(fake->mapped_buffers(), 0);
}

TEST(V4l2Camera, CountersAreReadableWhileCapturing) {
  FakeV4l2Script script;
  script.error_sequences = {1};
  auto fake = std::make_shared<FakeV4l2Device>(script);
  V4l2Camera camera(options_for(script), fake);
  ASSERT_TRUE(camera.start().ok());
  std::thread capture([&] {
    for (int i = 0; i < 200; ++i) (void)camera.next(1s);
  });
  std::uint64_t seen = 0;
  while (seen < 200) {
    const auto c = camera.counters();
    EXPECT_GE(c.frames, seen);
    seen = c.frames;
  }
  capture.join();
  EXPECT_EQ(camera.counters().dropped_error, 1u);
}

}  // namespace
}  // namespace spinewatch
