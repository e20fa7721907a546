// RecordingWriter → RecordingReader round trips, and recordings made with
// plain file writes the way v4l2-ctl makes them.
#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "recording_fixtures.hpp"
#include "spinewatch/capture/recording.hpp"
#include "test_support.hpp"

namespace spinewatch::test {
namespace {

using ::testing::HasSubstr;

struct WrittenFrame {
  View view;
  FrameInfo info;
  std::uint32_t seed;
};

// Frontal and lateral with irregular seq/t (a dropped frame, jitter), so a
// reader that invented metadata would be caught.
std::vector<WrittenFrame> irregular_frames() {
  return {{View::Frontal, {100, 1'000'000'000}, 1}, {View::Lateral, {7, 1'000'400'000}, 2},
          {View::Frontal, {101, 1'033'300'000}, 3}, {View::Lateral, {8, 1'033'900'000}, 4},
          {View::Frontal, {103, 1'100'100'000}, 5}, {View::Lateral, {9, 1'066'700'000}, 6},
          {View::Lateral, {10, 1'100'000'000}, 7}};
}

void write_recording(const std::filesystem::path& dir, const FrameFormat& format, double fps,
                     const std::vector<WrittenFrame>& frames, const nlohmann::json& subject = nullptr,
                     const std::string& notes = {}) {
  auto writer = RecordingWriter::create(dir, format, fps);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  for (const auto& f : frames) {
    auto st = writer->write(f.view, pattern_frame(format, f.info, f.seed));
    ASSERT_TRUE(st.ok()) << st.error().message;
  }
  auto st = writer->finish(subject, notes);
  ASSERT_TRUE(st.ok()) << st.error().message;
}

void expect_frames_read_back(RecordingReader& reader, const FrameFormat& format,
                             const std::vector<WrittenFrame>& frames) {
  std::size_t index[2] = {0, 0};
  for (const auto& f : frames) {
    const auto i = index[static_cast<int>(f.view)]++;
    auto frame = reader.read(f.view, i);
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    EXPECT_EQ(frame->format(), format);
    EXPECT_EQ(frame->sequence(), f.info.sequence);
    EXPECT_EQ(frame->timestamp_ns(), f.info.timestamp_ns);
    EXPECT_EQ(to_vector(frame->bytes()), pattern_bytes(format.frame_bytes(), f.seed))
        << to_string(f.view) << " frame " << i;
  }
  EXPECT_EQ(reader.frame_count(View::Frontal), index[0]);
  EXPECT_EQ(reader.frame_count(View::Lateral), index[1]);
}

void round_trip(const FrameFormat& format) {
  TempDir tmp;
  const auto dir = tmp / "rec";
  const auto frames = irregular_frames();
  const nlohmann::json subject = {{"name", "phantom-7"}, {"height_mm", 1712}};
  write_recording(dir, format, 29.97, frames, subject, "round trip");

  auto reader = RecordingReader::open(dir);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_TRUE(reader->warnings().empty());
  EXPECT_EQ(reader->info().format, format);
  EXPECT_DOUBLE_EQ(reader->info().fps, 29.97);
  EXPECT_EQ(reader->info().subject, subject);
  EXPECT_EQ(reader->info().notes, "round trip");
  expect_frames_read_back(*reader, format, frames);
}

TEST(RecordingRoundTrip, YuyvBitForBit) { round_trip(FrameFormat::packed(PixelFormat::YUYV, 32, 24)); }

TEST(RecordingRoundTrip, GreyBitForBit) { round_trip(FrameFormat::packed(PixelFormat::GREY, 32, 24)); }

TEST(RecordingRoundTrip, YuyvWithPaddedRows) { round_trip({PixelFormat::YUYV, 30, 20, 64}); }

TEST(RecordingRoundTrip, GreyWithPaddedRows) { round_trip({PixelFormat::GREY, 30, 20, 32}); }

TEST(RecordingRoundTrip, BytesPerLineWrittenOnlyWhenRowsArePadded) {
  TempDir tmp;
  const std::vector<WrittenFrame> one = {{View::Frontal, {0, 0}, 1}, {View::Lateral, {0, 0}, 2}};
  write_recording(tmp / "packed", FrameFormat::packed(PixelFormat::GREY, 30, 20), 30, one);
  write_recording(tmp / "padded", {PixelFormat::GREY, 30, 20, 32}, 30, one);
  const auto packed = nlohmann::json::parse(read_file(tmp / "packed" / "recording.json"));
  const auto padded = nlohmann::json::parse(read_file(tmp / "padded" / "recording.json"));
  EXPECT_FALSE(packed.contains("bytesperline"));
  EXPECT_EQ(padded.at("bytesperline"), 32);
  EXPECT_EQ(packed.at("pixel_format"), "GREY");
  EXPECT_FALSE(packed.contains("subject"));
  EXPECT_FALSE(packed.contains("notes"));
}

TEST(RecordingRoundTrip, WithoutFramesMetadataFramesGetIndexAndFpsTime) {
  TempDir tmp;
  const auto dir = tmp / "rec";
  const auto format = FrameFormat::packed(PixelFormat::YUYV, 16, 8);
  write_recording(dir, format, 30, irregular_frames());
  auto json = nlohmann::json::parse(read_file(dir / "recording.json"));
  json.erase("frames");
  write_file(dir / "recording.json", json.dump());

  auto reader = RecordingReader::open(dir);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  ASSERT_EQ(reader->frame_count(View::Frontal), 3u);
  ASSERT_EQ(reader->frame_count(View::Lateral), 4u);
  const std::uint32_t lateral_seeds[] = {2, 4, 6, 7};
  for (std::size_t i = 0; i < 4; ++i) {
    auto frame = reader->read(View::Lateral, i);
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    EXPECT_EQ(frame->sequence(), i);
    EXPECT_EQ(frame->timestamp_ns(), std::llround(static_cast<double>(i) * 1e9 / 30.0));
    EXPECT_EQ(to_vector(frame->bytes()), pattern_bytes(format.frame_bytes(), lateral_seeds[i]));
  }
}

TEST(RecordingRoundTrip, V4l2CtlStyleRecordingReplays) {
  // v4l2-ctl --stream-mmap --stream-to=FILE: payloads back to back, no header;
  // recording.json written by hand with only the required keys.
  TempDir tmp;
  const auto dir = tmp / "v4l2";
  const auto format = FrameFormat::packed(PixelFormat::YUYV, 320, 240);
  write_raw_recording(dir, format, 3,
                      R"({"pixel_format": "YUYV", "width": 320, "height": 240, "fps": 30})");

  auto reader = RecordingReader::open(dir);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_TRUE(reader->warnings().empty());
  EXPECT_EQ(reader->info().format, format);
  EXPECT_TRUE(reader->info().subject.is_null());
  for (View view : kViews) {
    ASSERT_EQ(reader->frame_count(view), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      auto frame = reader->read(view, i);
      ASSERT_TRUE(frame.ok()) << frame.error().message;
      const std::uint32_t seed = (view == View::Frontal ? 0 : 1000) + static_cast<std::uint32_t>(i);
      EXPECT_EQ(to_vector(frame->bytes()), pattern_bytes(format.frame_bytes(), seed));
      EXPECT_EQ(frame->luma().at(5, 7), frame->bytes()[7 * 640 + 5 * 2]);
    }
  }
  auto beyond = reader->read(View::Frontal, 3);
  ASSERT_FALSE(beyond.ok());
  EXPECT_THAT(beyond.error().message, HasSubstr("frontal.raw: frame 3 is out of range (the stream has 3 frames)"));
}

TEST(RecordingWriter, RejectsFrameOfAnotherFormat) {
  TempDir tmp;
  auto writer = RecordingWriter::create(tmp / "rec", FrameFormat::packed(PixelFormat::YUYV, 16, 8), 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  auto st = writer->write(View::Lateral, pattern_frame(FrameFormat::packed(PixelFormat::GREY, 16, 8), {}, 1));
  ASSERT_FALSE(st.ok());
  EXPECT_THAT(st.error().message, HasSubstr("lateral.raw: frame format GREY 16x8 bpl 16 differs from the "
                                            "recording's YUYV 16x8 bpl 32"));
}

TEST(RecordingWriter, RejectsFrameOfWrongSize) {
  TempDir tmp;
  const auto format = FrameFormat::packed(PixelFormat::GREY, 16, 8);
  auto writer = RecordingWriter::create(tmp / "rec", format, 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  auto st = writer->write(View::Frontal, Frame::owning(format, {}, std::vector<std::uint8_t>(100)));
  ASSERT_FALSE(st.ok());
  EXPECT_THAT(st.error().message, HasSubstr("frontal.raw: frame of 100 bytes, expected 128"));
}

TEST(RecordingWriter, PaddingBeyondTheImageIsNotWritten) {
  TempDir tmp;
  const auto format = FrameFormat::packed(PixelFormat::GREY, 16, 8);
  auto writer = RecordingWriter::create(tmp / "rec", format, 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  auto payload = pattern_bytes(128 + 64, 5);  // a sizeimage larger than bytesperline x height
  for (View view : kViews) ASSERT_TRUE(writer->write(view, Frame::copy_of(format, {}, payload)).ok());
  ASSERT_TRUE(writer->finish().ok());
  EXPECT_EQ(std::filesystem::file_size(tmp / "rec" / "frontal.raw"), 128u);
  auto reader = RecordingReader::open(tmp / "rec");
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  auto frame = reader->read(View::Lateral, 0);
  ASSERT_TRUE(frame.ok()) << frame.error().message;
  payload.resize(128);
  EXPECT_EQ(to_vector(frame->bytes()), payload);
}

TEST(RecordingWriter, RejectsSequenceThatDoesNotIncrease) {
  TempDir tmp;
  const auto format = FrameFormat::packed(PixelFormat::GREY, 16, 8);
  auto writer = RecordingWriter::create(tmp / "rec", format, 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  ASSERT_TRUE(writer->write(View::Frontal, pattern_frame(format, {5, 100}, 1)).ok());
  auto same_seq = writer->write(View::Frontal, pattern_frame(format, {5, 200}, 2));
  ASSERT_FALSE(same_seq.ok());
  EXPECT_THAT(same_seq.error().message, HasSubstr("frame seq 5 does not follow the previous 5"));
  auto earlier = writer->write(View::Frontal, pattern_frame(format, {6, 50}, 2));
  ASSERT_FALSE(earlier.ok());
  EXPECT_THAT(earlier.error().message, HasSubstr("frame t_ns 50 is before the previous 100"));
}

TEST(RecordingWriter, RejectsBadFormatAndUnwritableDirectory) {
  TempDir tmp;
  auto bad_bpl = RecordingWriter::create(tmp / "a", {PixelFormat::YUYV, 16, 8, 20}, 30);
  ASSERT_FALSE(bad_bpl.ok());
  EXPECT_THAT(bad_bpl.error().message, HasSubstr("bytesperline must be at least 32"));
  auto bad_fps = RecordingWriter::create(tmp / "b", FrameFormat::packed(PixelFormat::GREY, 16, 8), 0);
  ASSERT_FALSE(bad_fps.ok());
  EXPECT_THAT(bad_fps.error().message, HasSubstr("at 0 fps"));

  write_file(tmp / "plain-file", "x");
  auto under_file = RecordingWriter::create(tmp / "plain-file" / "rec", FrameFormat::packed(PixelFormat::GREY, 4, 4), 30);
  ASSERT_FALSE(under_file.ok());
  EXPECT_THAT(under_file.error().message, HasSubstr((tmp / "plain-file" / "rec").string() + ": cannot create"));
}

TEST(RecordingWriter, FinishTwiceAndWriteAfterFinishAreErrors) {
  TempDir tmp;
  const auto format = FrameFormat::packed(PixelFormat::GREY, 4, 4);
  auto writer = RecordingWriter::create(tmp / "rec", format, 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  for (View view : kViews) ASSERT_TRUE(writer->write(view, pattern_frame(format, {0, 0}, 1)).ok());
  ASSERT_TRUE(writer->finish().ok());
  auto again = writer->finish();
  ASSERT_FALSE(again.ok());
  EXPECT_THAT(again.error().message, HasSubstr("finish() was already called"));
  auto late = writer->write(View::Frontal, pattern_frame(format, {1, 1}, 2));
  ASSERT_FALSE(late.ok());
  EXPECT_THAT(late.error().message, HasSubstr("after finish()"));
}

TEST(RecordingWriter, FinishWithAnEmptyStreamWritesButReportsIt) {
  TempDir tmp;
  const auto format = FrameFormat::packed(PixelFormat::GREY, 4, 4);
  auto writer = RecordingWriter::create(tmp / "rec", format, 30);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  ASSERT_TRUE(writer->write(View::Frontal, pattern_frame(format, {0, 0}, 1)).ok());
  auto st = writer->finish();
  ASSERT_FALSE(st.ok());
  EXPECT_THAT(st.error().message, HasSubstr("the lateral stream is empty"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "rec" / "recording.json"));
  auto reader = RecordingReader::open(tmp / "rec");
  ASSERT_FALSE(reader.ok());
  EXPECT_THAT(reader.error().message, HasSubstr("lateral.raw: empty stream"));
}

TEST(RecordingWriter, OverwritingARecordingReplacesItsMetadata) {
  TempDir tmp;
  const auto dir = tmp / "rec";
  const auto format = FrameFormat::packed(PixelFormat::GREY, 4, 4);
  write_recording(dir, format, 30, irregular_frames());
  const std::vector<WrittenFrame> second = {{View::Frontal, {0, 0}, 11}, {View::Lateral, {0, 0}, 12}};
  write_recording(dir, format, 15, second);
  auto reader = RecordingReader::open(dir);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_DOUBLE_EQ(reader->info().fps, 15);
  expect_frames_read_back(*reader, format, second);
}

TEST(RecordingView, Names) {
  EXPECT_EQ(to_string(View::Frontal), "frontal");
  EXPECT_EQ(to_string(View::Lateral), "lateral");
}

}  // namespace
}  // namespace spinewatch::test
