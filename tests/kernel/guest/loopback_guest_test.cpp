// Known content through a real driver: phantom frames go out of vivid's HDMI
// video output, loop into its HDMI capture and come back through our V4L2
// source; the estimator must then see exactly what a replay of the phantom
// recording sees.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "guest_env.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/replay/replay.hpp"
#include "video_output.hpp"
#include "vivid_controls.hpp"

namespace spinewatch::kernel_test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// The pixels of a frame, without the driver's row padding.
std::vector<std::uint8_t> pixels(const Frame& frame) {
  const auto& f = frame.format();
  std::vector<std::uint8_t> out;
  out.reserve(std::size_t{f.min_bytesperline()} * f.height);
  for (std::uint32_t y = 0; y < f.height; ++y) {
    const auto row = frame.bytes().subspan(std::size_t{y} * f.bytesperline, f.min_bytesperline());
    out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

// The same pixels laid out with the output's stride.
std::vector<std::uint8_t> with_stride(const std::vector<std::uint8_t>& packed, const FrameFormat& f) {
  std::vector<std::uint8_t> out(f.frame_bytes(), 0);
  for (std::uint32_t y = 0; y < f.height; ++y) {
    std::memcpy(out.data() + std::size_t{y} * f.bytesperline, packed.data() + std::size_t{y} * f.min_bytesperline(),
                f.min_bytesperline());
  }
  return out;
}

Status set_control(const std::string& path, std::uint32_t id, std::int32_t value, const char* name) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return Error{fmt::format("{}: open: {}", path, std::strerror(errno))};
  v4l2_control c{id, value};
  const int rc = ::ioctl(fd, VIDIOC_S_CTRL, &c);
  const int err = errno;
  ::close(fd);
  if (rc < 0) return Error{fmt::format("{}: set {} to {}: {}", path, name, value, std::strerror(err))};
  return Ok{};
}

// Every posture line of a replay, with the run-dependent latency zeroed.
std::vector<std::string> replay_lines(const fs::path& dir, std::uint64_t& tracked) {
  std::vector<std::string> lines;
  tracked = 0;
  auto stats = replay_recording(dir, ReplayOptions{}, [&](const Posture& p) -> Status {
    Posture q = p;
    q.latency_us = 0;
    if (q.state != TrackingState::Lost) ++tracked;
    lines.push_back(encode_posture(q));
    return Ok{};
  });
  EXPECT_TRUE(stats.ok()) << dir << ": " << (stats ? "" : stats.error().message);
  return lines;
}

TEST(Loopback, PhantomBytesRoundTripAndEstimatorAgrees) {
  SW_REQUIRE_ENV("SW_LOOP_SKIP", "SW_LOOP_CAP", "SW_LOOP_OUT", "SW_PHANTOM", "SW_TMP");
  const fs::path phantom = env_or_empty("SW_PHANTOM");
  auto reader = RecordingReader::open(phantom);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const FrameFormat format = reader->info().format;
  ASSERT_EQ(format.pixel_format, PixelFormat::YUYV);

  const std::string cap_path = env_or_empty("SW_LOOP_CAP");
  ASSERT_TRUE(set_control(cap_path, vivid::kLoopVideo, 1, "loop_video").ok());
  ASSERT_TRUE(set_control(cap_path, vivid::kOsdTextMode, 2, "osd_text_mode").ok());  // no text over the video

  auto output = VideoOutput::open(env_or_empty("SW_LOOP_OUT"), format);
  ASSERT_TRUE(output.ok()) << output.error().message;
  V4l2CameraOptions options;
  options.path = cap_path;
  options.name = "loop";
  options.width = format.width;
  options.height = format.height;
  V4l2Camera camera(options);
  ASSERT_TRUE(camera.start().ok());
  ASSERT_TRUE((*output)->start().ok());

  const fs::path captured_dir = fs::path(env_or_empty("SW_TMP")) / "loopback";
  fs::remove_all(captured_dir);
  auto writer = RecordingWriter::create(captured_dir, camera.format(), reader->info().fps);
  ASSERT_TRUE(writer.ok()) << writer.error().message;

  // Show each frame until it comes back; from the first frame that made the
  // round trip on, every captured frame must be the one shown or the one
  // before (buffers still in the output queue), byte for byte.
  std::uint64_t frames_compared = 0;
  bool looping = false;
  std::vector<std::uint8_t> previous;
  for (View view : kViews) {
    for (std::size_t i = 0; i < reader->frame_count(view); ++i) {
      SCOPED_TRACE(fmt::format("{} frame {}", to_string(view), i));
      auto original = reader->read(view, i);
      ASSERT_TRUE(original.ok()) << original.error().message;
      const auto expected = pixels(*original);
      (*output)->show(with_stride(expected, (*output)->format()));
      const auto deadline = std::chrono::steady_clock::now() + 5s;
      bool arrived = false;
      while (!arrived && std::chrono::steady_clock::now() < deadline) {
        auto frame = camera.next(500ms);
        if (!frame) continue;
        const auto got = pixels(*frame);
        ++frames_compared;
        if (got == expected) {
          arrived = true;
          looping = true;
          // The captured bytes with the original's sequence and time, so that
          // the estimator's tracking sees the same timeline.
          const Frame copy = Frame::copy_of(frame->format(), original->info(), frame->bytes());
          ASSERT_TRUE(writer->write(view, copy).ok());
        } else if (looping) {
          ASSERT_TRUE(got == previous) << "a captured frame is neither the frame shown nor the one before";
        }
      }
      ASSERT_TRUE(arrived) << "not captured back within 5 s (output buffers fed: " << (*output)->buffers_fed() << ")";
      previous = expected;
    }
  }
  camera.stop();
  ASSERT_TRUE(writer->finish(nullptr, "kernel loopback of " + phantom.string()).ok());
  fs::copy_file(phantom / "calibration.yaml", captured_dir / "calibration.yaml");
  // The scene's background goes with the frames, as `record` copies the
  // station's: both replays then start from the same empty scene.
  for (const char* png : {"background_frontal.png", "background_lateral.png"})
    if (fs::exists(phantom / png)) fs::copy_file(phantom / png, captured_dir / png);
  std::printf("loopback: %llu captured frames compared for %zu + %zu frames shown\n",
              static_cast<unsigned long long>(frames_compared), reader->frame_count(View::Frontal),
              reader->frame_count(View::Lateral));

  std::uint64_t tracked_original = 0, tracked_captured = 0;
  const auto expected_lines = replay_lines(phantom, tracked_original);
  const auto captured_lines = replay_lines(captured_dir, tracked_captured);
  ASSERT_FALSE(expected_lines.empty());
  // Guards against comparing two empty results: the phantom's person is tracked.
  EXPECT_GT(tracked_original, 0u);
  std::printf("loopback: %zu postures, %llu tracked\n", expected_lines.size(),
              static_cast<unsigned long long>(tracked_original));
  ASSERT_EQ(captured_lines.size(), expected_lines.size());
  for (std::size_t i = 0; i < expected_lines.size(); ++i) EXPECT_EQ(captured_lines[i], expected_lines[i]) << "pair " << i;
}

}  // namespace
}  // namespace spinewatch::kernel_test
