// record → replay round trip (issue #6 item 5): two fake V4L2 cameras, one
// skipping a sequence number and one flagging a frame bad, through the real
// V4l2Camera ioctl paths and the Recorder into a recording directory, read
// back with RecordingReader and replayed with `spinewatch replay`.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/capture/recorder.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

V4l2CameraOptions options_for(const FakeV4l2Script& script, const char* name) {
  V4l2CameraOptions o;
  o.path = script.path;
  o.name = name;
  o.retry_initial = 1ms;
  o.retry_max = 4ms;
  return o;
}

std::vector<std::uint64_t> range_without(std::uint64_t last, std::uint64_t missing) {
  std::vector<std::uint64_t> v;
  for (std::uint64_t s = 0; s <= last; ++s)
    if (s != missing) v.push_back(s);
  return v;
}

struct Delivered {
  std::vector<FrameInfo> info;
  std::vector<std::vector<std::uint8_t>> bytes;
};

class RecordReplay : public ::testing::Test {
 protected:
  static constexpr std::uint64_t kFrames = 20;
  void SetUp() override {
    FakeV4l2Script frontal_script, lateral_script;
    frontal_script.path = "/dev/video-frontal";
    frontal_script.skipped_sequences = {5};  // never delivered: a gap
    lateral_script.path = "/dev/video-lateral";
    lateral_script.error_sequences = {9};  // V4L2_BUF_FLAG_ERROR: dropped by the camera
    frontal_ = std::make_unique<V4l2Camera>(options_for(frontal_script, "frontal"),
                                            std::make_shared<FakeV4l2Device>(frontal_script));
    lateral_ = std::make_unique<V4l2Camera>(options_for(lateral_script, "lateral"),
                                            std::make_shared<FakeV4l2Device>(lateral_script));
    ASSERT_TRUE(frontal_->start().ok());
    ASSERT_TRUE(lateral_->start().ok());
  }
  RecorderOptions options() {
    RecorderOptions o;
    o.frames = kFrames;
    o.write_calibration = [](const std::filesystem::path& p) { return save_calibration(p, CameraRig::default_rig()); };
    o.on_frame = [this](View v, const Frame& f) {
      auto& d = delivered_[static_cast<int>(v)];
      d.info.push_back(f.info());
      d.bytes.emplace_back(f.bytes().begin(), f.bytes().end());
    };
    return o;
  }
  test::TempDir dir_;
  std::unique_ptr<V4l2Camera> frontal_, lateral_;
  Delivered delivered_[2];
};

TEST_F(RecordReplay, WhatTheCamerasDeliveredIsWhatTheRecordingHolds) {
  Recorder recorder(*frontal_, *lateral_, options());
  auto summary = recorder.record(dir_ / "rec");
  ASSERT_TRUE(summary) << summary.error().message;
  EXPECT_EQ(summary->written[0], kFrames);
  EXPECT_EQ(summary->written[1], kFrames);
  EXPECT_FALSE(summary->stopped);
  EXPECT_EQ(summary->counters[0].dropped_gap, 1u);
  EXPECT_EQ(summary->counters[1].dropped_error, 1u);

  // The real driver sequence numbers: frontal lacks 5, lateral lacks 9.
  const std::vector<std::uint64_t> expected_seq[2] = {range_without(kFrames, 5), range_without(kFrames, 9)};
  auto reader = RecordingReader::open(dir_ / "rec");
  ASSERT_TRUE(reader) << reader.error().message;
  EXPECT_TRUE(reader->warnings().empty());
  for (int v = 0; v < 2; ++v) {
    const auto view = static_cast<View>(v);
    ASSERT_EQ(delivered_[v].info.size(), kFrames);
    ASSERT_EQ(reader->frame_count(view), kFrames);
    for (std::size_t i = 0; i < kFrames; ++i) {
      const FrameInfo& recorded = reader->info().frames[v][i];
      EXPECT_EQ(delivered_[v].info[i].sequence, expected_seq[v][i]) << to_string(view) << " " << i;
      EXPECT_EQ(recorded.sequence, delivered_[v].info[i].sequence) << to_string(view) << " " << i;
      EXPECT_EQ(recorded.timestamp_ns, delivered_[v].info[i].timestamp_ns) << to_string(view) << " " << i;
      auto frame = reader->read(view, i);
      ASSERT_TRUE(frame) << frame.error().message;
      const auto bytes = frame->bytes();
      ASSERT_TRUE(std::equal(bytes.begin(), bytes.end(), delivered_[v].bytes[i].begin(), delivered_[v].bytes[i].end()))
          << to_string(view) << " frame " << i;
      // And the bytes are the fake's own pattern for that sequence number.
      const auto& f = frame->format();
      EXPECT_EQ(bytes[std::size_t{f.height - 1} * f.bytesperline + 7],
                FakeV4l2Device::pattern(recorded.sequence, 7, f.height - 1));
    }
    // Timestamps are the driver's (CLOCK_MONOTONIC at one frame period), not re-made at 1/fps from zero.
    EXPECT_GT(reader->info().frames[v][0].timestamp_ns, 0);
    EXPECT_NEAR(double(reader->info().frames[v][1].timestamp_ns - reader->info().frames[v][0].timestamp_ns), 1e9 / 30, 2e3);
  }
  EXPECT_TRUE(std::filesystem::exists(dir_ / "rec/calibration.yaml"));
  EXPECT_TRUE(load_calibration(dir_ / "rec/calibration.yaml").ok());

  // Replay pairs by timestamp: frontal 9 and lateral 5 have no partner and are reported, never mispaired.
  auto r = test::run_cli("replay --recording " + (dir_ / "rec").string() + " --out " + (dir_ / "p.ndjson").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 frames had no partner"), std::string::npos) << r.output;
  std::map<std::uint64_t, std::int64_t> t_of[2];
  for (int v = 0; v < 2; ++v)
    for (const auto& info : delivered_[v].info) t_of[v][info.sequence] = info.timestamp_ns;
  std::vector<std::uint64_t> seqs;
  std::ifstream in(dir_ / "p.ndjson");
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    const auto seq = j["seq"].get<std::uint64_t>();
    seqs.push_back(seq);
    ASSERT_TRUE(t_of[0].count(seq) && t_of[1].count(seq)) << seq;
    // The pair's time is the middle of its two frames' driver timestamps.
    EXPECT_EQ(j["t_ns"].get<std::int64_t>(), t_of[0][seq] + (t_of[1][seq] - t_of[0][seq]) / 2) << seq;
  }
  std::vector<std::uint64_t> both;
  for (std::uint64_t s = 0; s <= kFrames; ++s)
    if (s != 5 && s != 9) both.push_back(s);
  EXPECT_EQ(seqs, both);
}

TEST_F(RecordReplay, StopEndsTheRecordingCleanly) {
  // Cameras at their real rate, so that stopping lands mid-stream.
  FakeV4l2Script scripts[2];
  std::unique_ptr<V4l2Camera> cameras[2];
  for (int v = 0; v < 2; ++v) {
    scripts[v].path = v == 0 ? "/dev/video-a" : "/dev/video-b";
    scripts[v].paced = true;
    cameras[v] = std::make_unique<V4l2Camera>(options_for(scripts[v], v == 0 ? "frontal" : "lateral"),
                                              std::make_shared<FakeV4l2Device>(scripts[v]));
    ASSERT_TRUE(cameras[v]->start().ok());
  }
  auto o = options();
  o.frames.reset();  // only stop() ends it
  Recorder recorder(*cameras[0], *cameras[1], std::move(o));
  std::jthread stopper([&] {
    std::this_thread::sleep_for(150ms);
    recorder.stop();
  });
  auto summary = recorder.record(dir_ / "rec");
  ASSERT_TRUE(summary) << summary.error().message;
  EXPECT_TRUE(summary->stopped);
  auto reader = RecordingReader::open(dir_ / "rec");
  ASSERT_TRUE(reader) << reader.error().message;
  for (int v = 0; v < 2; ++v) {
    EXPECT_EQ(reader->frame_count(static_cast<View>(v)), summary->written[v]);
    EXPECT_GE(summary->written[v], 2u);
    EXPECT_LE(summary->written[v], 10u);  // 150 ms at 30 fps, with slack for a loaded machine
  }
}

TEST_F(RecordReplay, CamerasThatDisagreeOnTheFormatAreAnError) {
  FakeV4l2Script grey;
  grey.path = "/dev/video-grey";
  auto options = options_for(grey, "lateral");
  options.pixel_format = PixelFormat::GREY;
  V4l2Camera lateral(options, std::make_shared<FakeV4l2Device>(grey));
  ASSERT_TRUE(lateral.start().ok());
  Recorder recorder(*frontal_, lateral, this->options());
  auto summary = recorder.record(dir_ / "rec");
  ASSERT_FALSE(summary);
  EXPECT_NE(summary.error().message.find("disagree on the format"), std::string::npos) << summary.error().message;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "rec"));
}

}  // namespace
}  // namespace spinewatch
