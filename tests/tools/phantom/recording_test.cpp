#include <gtest/gtest.h>

#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "spinewatch/capture/recording.hpp"
#include "spinewatch/estimator/posture_json.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

TEST(PhantomRecording, ReadsBackWithRecordingReader) {
  PhantomOptions options;
  options.scenario = "lateral_left";
  options.frames = 20;
  options.empty_frames = 5;
  options.seed = 11;
  auto sequence = PhantomSequence::create(options);
  ASSERT_TRUE(sequence);
  test::TempDir dir;
  auto written = write_recording(*sequence, dir / "rec");
  ASSERT_TRUE(written) << written.error().message;

  auto reader = RecordingReader::open(dir / "rec");
  ASSERT_TRUE(reader) << reader.error().message;
  const RecordingInfo& info = reader->info();
  EXPECT_EQ(info.format, FrameFormat::packed(PixelFormat::YUYV, 320, 240));
  EXPECT_EQ(info.fps, 30.0);
  ASSERT_EQ(reader->frame_count(View::Frontal), 25u);
  ASSERT_EQ(reader->frame_count(View::Lateral), 25u);
  for (std::size_t i = 0; i < 25; ++i) {
    EXPECT_EQ(info.frames[1][i].sequence, i);
    EXPECT_EQ(info.frames[1][i].timestamp_ns, std::llround(double(i) * 1e9 / 30));
  }
  EXPECT_NE(info.notes.find("scenario=lateral_left"), std::string::npos) << info.notes;
  EXPECT_NE(info.notes.find("seed=11"), std::string::npos) << info.notes;
  auto subject = parse_subject(info.subject, "recording.json subject");
  ASSERT_TRUE(subject) << subject.error().message;
  EXPECT_TRUE(subject->joint_factors.has_value());

  // The bytes on disk are the rendered luma with U = V = 128.
  const PhantomFrame expected = sequence->render(17);
  for (View view : kViews) {
    auto frame = reader->read(view, 17);
    ASSERT_TRUE(frame) << frame.error().message;
    const LumaView luma = frame->luma();
    const cv::Mat& want = expected.luma[static_cast<int>(view)];
    int mismatches = 0;
    for (int y = 0; y < 240; ++y)
      for (int x = 0; x < 320; ++x) mismatches += luma.at(x, y) != want.at<std::uint8_t>(y, x);
    EXPECT_EQ(mismatches, 0);
    for (std::size_t k = 1; k < frame->bytes().size(); k += 2) ASSERT_EQ(frame->bytes()[k], 128);
  }

  auto rig = load_calibration(dir / "rec" / "calibration.yaml");
  ASSERT_TRUE(rig) << rig.error().message;
  EXPECT_TRUE(rig->lateral.R.isApprox(options.rig.lateral.R));
  EXPECT_TRUE(rig->frontal.t.isApprox(options.rig.frontal.t));

  for (View view : kViews) {
    const auto png = dir / "rec" / (view == View::Frontal ? "background_frontal.png" : "background_lateral.png");
    const cv::Mat background = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(background.empty()) << png;
    EXPECT_EQ(cv::countNonZero(background != sequence->background(view)), 0);
  }
}

TEST(PhantomRecording, GroundTruthMatchesTheSchemaAndTheFrames) {
  PhantomOptions options;
  options.scenario = "seated_flexion";
  options.frames = 12;
  options.empty_frames = 3;
  auto sequence = PhantomSequence::create(options);
  ASSERT_TRUE(sequence);
  test::TempDir dir;
  ASSERT_TRUE(write_recording(*sequence, dir.path()));
  const auto path = dir / "ground_truth.ndjson";
  EXPECT_EQ(test::validate_ndjson(path), "");

  std::istringstream lines(test::read_file(path));
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    auto posture = decode_posture(line, "ground_truth.ndjson:" + std::to_string(n + 1));
    ASSERT_TRUE(posture) << posture.error().message;
    EXPECT_EQ(posture->seq, std::uint64_t(n));
    EXPECT_EQ(posture->t_ns, frame_time_ns(std::uint64_t(n)));
    EXPECT_EQ(posture->fit.cost, 0);
    EXPECT_EQ(posture->latency_us, 0);
    EXPECT_EQ(posture->state, n < 3 ? TrackingState::Lost : TrackingState::Tracking);
    if (n >= 3) {
      const Posture truth = sequence->ground_truth(n);
      EXPECT_LT((*posture->neck - *truth.neck).norm(), 0.01);
      EXPECT_LT((*posture->waist - *truth.waist).norm(), 0.01);
      EXPECT_LT(((*posture->vertebrae)[8].body_center - (*truth.vertebrae)[8].body_center).norm(), 0.01);
      // Seated: the pelvis sits at the seat, well below standing height.
      EXPECT_LT(posture->waist->y(), 0.5 * 1750);
    }
    ++n;
  }
  EXPECT_EQ(n, 15);
}

TEST(PhantomRecording, UnwritableDirectoryIsAnError) {
  PhantomOptions options;
  options.frames = 2;
  options.empty_frames = 0;
  auto sequence = PhantomSequence::create(options);
  ASSERT_TRUE(sequence);
  test::TempDir dir;
  test::write_file(dir / "file", "not a directory");
  auto status = write_recording(*sequence, dir / "file" / "rec");
  ASSERT_FALSE(status);
  EXPECT_NE(status.error().message.find("file"), std::string::npos) << status.error().message;
}

}  // namespace
}  // namespace spinewatch::phantom
