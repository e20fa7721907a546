// The daemon's camera chain (camera pair source + pipeline, as spinewatchd
// builds it) on two vivid cameras while one of them is unplugged with
// vivid's "Disconnect" button and comes back: the chain keeps running,
// logs the loss once, marks the gap with one `lost` line flagged
// `camera_lost`, counts it, and pairs again without a restart.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "driver_query.hpp"
#include "guest_env.hpp"
#include "pipeline/pipeline.hpp"
#include "spinewatch/daemon/camera_pair_source.hpp"
#include "vivid_controls.hpp"

namespace spinewatch::kernel_test {
namespace {

using namespace std::chrono_literals;

struct Lines {
  std::mutex mutex;
  std::vector<Posture> postures;
  void add(const Posture& p) {
    std::lock_guard lock(mutex);
    postures.push_back(p);
  }
  std::vector<Posture> snapshot() {
    std::lock_guard lock(mutex);
    return postures;
  }
};

std::size_t pairs_after_marker(const std::vector<Posture>& lines) {
  auto marker = std::find_if(lines.begin(), lines.end(), [](const Posture& p) { return p.fit.flag == "camera_lost"; });
  if (marker == lines.end()) return 0;
  return static_cast<std::size_t>(lines.end() - marker - 1);
}

bool wait_for(const std::function<bool()>& done, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
  return true;
}

std::size_t count_containing(const std::vector<std::string>& log, const std::string& text) {
  return static_cast<std::size_t>(
      std::count_if(log.begin(), log.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; }));
}

TEST(Daemon, CameraUnpluggedAndBackIsMarkedOnceAndPairingResumes) {
  SW_REQUIRE_ENV("SW_V4L2_SKIP", "SW_VIDEO_A", "SW_VIDEO_B");
  const std::string frontal = env_or_empty("SW_VIDEO_A"), lateral = env_or_empty("SW_VIDEO_B");
  const auto fps = driver_fps(frontal);
  ASSERT_TRUE(fps) << "VIDIOC_G_PARM on " << frontal;

  // What the daemon logs, kept for the test (and still printed on the console).
  auto ring = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(512);
  spdlog::default_logger()->sinks().push_back(ring);

  CameraPairOptions o;
  for (auto* c : {&o.frontal, &o.lateral}) {
    c->width = 320;
    c->height = 240;
    c->fps = *fps;
    c->buffers = 4;
    c->retry_initial = 50ms;
    c->retry_max = 400ms;
  }
  o.frontal.path = frontal;
  o.frontal.name = "frontal";
  o.lateral.path = lateral;
  o.lateral.name = "lateral";
  o.trigger.mode = sync::TriggerMode::FreeRun;
  auto source = open_camera_pair_source(o);
  ASSERT_TRUE(source.ok()) << source.error().message;

  Lines lines;
  // The stand-in estimator: every pair "init" (the estimator is proven elsewhere;
  // here only what reaches the stream matters).
  auto estimate = [](const FramePair& pair) {
    EXPECT_FALSE(pair.camera_lost) << "a marker reached the estimator";
    Posture p;
    p.state = TrackingState::Init;
    return p;
  };
  Pipeline pipeline(std::move(source).value(), estimate, [&](const Posture& p, const FramePair&) { lines.add(p); }, {.pair_queue = 16});
  pipeline.start();
  ASSERT_TRUE(wait_for([&] { return lines.snapshot().size() >= 10; }, 20s)) << "no pairs before the unplug";

  {
    const int fd = ::open(lateral.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(fd, 0) << lateral << ": " << std::strerror(errno);
    v4l2_control press{vivid::kDisconnect, 1};
    ASSERT_EQ(::ioctl(fd, VIDIOC_S_CTRL, &press), 0) << "VIDIOC_S_CTRL Disconnect: " << std::strerror(errno);
    ::close(fd);
  }
  const bool resumed = wait_for([&] { return pairs_after_marker(lines.snapshot()) >= 10; }, 30s);
  const PipelineStats stats = pipeline.stats();
  pipeline.stop();
  spdlog::default_logger()->sinks().pop_back();
  const std::vector<Posture> out = lines.snapshot();
  const std::vector<std::string> log = ring->last_formatted();
  ASSERT_TRUE(resumed) << out.size() << " lines, " << pairs_after_marker(out) << " after a camera_lost marker";

  std::size_t markers = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(out[i].seq, out[i - 1].seq);
      EXPECT_GE(out[i].t_ns, out[i - 1].t_ns) << "line " << i;
    }
    if (out[i].fit.flag == "camera_lost") {
      ++markers;
      EXPECT_EQ(out[i].state, TrackingState::Lost);
      EXPECT_FALSE(out[i].vertebrae);
    } else {
      EXPECT_EQ(out[i].state, TrackingState::Init);
    }
  }
  EXPECT_EQ(markers, 1u);
  EXPECT_EQ(stats.source.camera[1].losses, 1u);
  EXPECT_EQ(stats.source.camera[1].restarts, 1u);
  EXPECT_EQ(stats.source.camera[0].losses, 0u);
  EXPECT_EQ(stats.source.camera[0].restarts, 0u);
  // Logged once each way, however many reopen attempts it took.
  EXPECT_EQ(count_containing(log, "lateral: device lost"), 1u);
  EXPECT_EQ(count_containing(log, "lateral: device back"), 1u);
}

// The libcamera path (LibcameraCamera counts Camera::disconnected as a
// loss; the pair source marks it as above) needs a camera libcamera can
// drive in the guest: vimc. Debian's 6.1 kernel is built without it
// (CONFIG_VIDEO_VIMC is not set: drivers/media/test-drivers holds vivid
// only), and libcamera has no pipeline handler for vivid. Registered so
// that the gap is visible in every run, and so that a guest kernel that
// has vimc makes this test fail until it is written.
TEST(Daemon, LibcameraDisconnectUnderVimc) {
  if (!std::filesystem::exists("/sys/bus/platform/drivers/vimc") && !std::filesystem::exists("/sys/module/vimc"))
    GTEST_SKIP() << "no vimc in the guest kernel (Debian's linux-image 6.1 ships no vimc module; libcamera cannot "
                    "drive vivid): LibcameraCamera's disconnect handling is not tested against a kernel";
  FAIL() << "vimc is loaded: the libcamera disconnect test is to be written for it";
}

}  // namespace
}  // namespace spinewatch::kernel_test
