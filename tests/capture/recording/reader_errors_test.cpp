// Every bad recording gets one message naming the file and the problem;
// a truncated last frame is dropped with a warning.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "recording_fixtures.hpp"
#include "spinewatch/capture/recording.hpp"
#include "test_support.hpp"

namespace spinewatch::test {
namespace {

using ::testing::HasSubstr;

const FrameFormat kYuyv = FrameFormat::packed(PixelFormat::YUYV, 4, 4);  // 32-byte frames
const std::string kYuyvJson = R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30})";

class RecordingReaderErrors : public ::testing::Test {
 protected:
  std::filesystem::path dir() const { return tmp_ / "rec"; }
  std::string json_path() const { return (dir() / "recording.json").string(); }
  std::string frontal_path() const { return (dir() / "frontal.raw").string(); }

  // A two-frame YUYV 4x4 recording with the given recording.json.
  void make(const std::string& json, std::size_t frames = 2) { write_raw_recording(dir(), kYuyv, frames, json); }

  std::string open_error() const {
    auto reader = RecordingReader::open(dir());
    return reader.ok() ? std::string("(opened without error)") : reader.error().message;
  }

  TempDir tmp_;
};

TEST_F(RecordingReaderErrors, MissingDirectory) {
  EXPECT_EQ(open_error(), dir().string() + ": no such recording directory");
}

TEST_F(RecordingReaderErrors, DirectoryIsAFile) {
  write_file(dir(), "not a directory");
  EXPECT_THAT(open_error(), HasSubstr(dir().string() + ": not a directory"));
}

TEST_F(RecordingReaderErrors, MissingRecordingJson) {
  make(kYuyvJson);
  std::filesystem::remove(dir() / "recording.json");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": missing"));
}

TEST_F(RecordingReaderErrors, MissingRawFiles) {
  make(kYuyvJson);
  std::filesystem::remove(dir() / "lateral.raw");
  EXPECT_THAT(open_error(), HasSubstr((dir() / "lateral.raw").string() + ": missing"));
  std::filesystem::remove(dir() / "frontal.raw");
  EXPECT_THAT(open_error(), HasSubstr(frontal_path() + ": missing"));
}

TEST_F(RecordingReaderErrors, BadJsonSyntaxNamesTheLine) {
  make("{\n  \"pixel_format\": \"YUYV\",\n  \"width\": 4,,\n  \"height\": 4\n}");
  const auto message = open_error();
  EXPECT_THAT(message, HasSubstr(json_path() + ": invalid JSON"));
  EXPECT_THAT(message, HasSubstr("line 3"));
}

// Found by mutating recording.json (issue 17): a number beyond double
// range threw out of the parser and aborted `replay` (SIGABRT).
TEST_F(RecordingReaderErrors, ANumberBeyondDoubleRangeIsAnErrorWithItsLine) {
  make("{\n  \"pixel_format\": \"YUYV\",\n  \"width\": 4,\n  \"height\": 4,\n  \"fps\": 1e309\n}");
  const auto message = open_error();
  EXPECT_THAT(message, HasSubstr(json_path() + ": invalid JSON: line 5: number overflow parsing '1e309'"));
}

TEST_F(RecordingReaderErrors, NotAnObject) {
  make("[1, 2]");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": must be a JSON object"));
}

class MissingField : public RecordingReaderErrors, public ::testing::WithParamInterface<const char*> {};

TEST_P(MissingField, IsNamed) {
  auto json = nlohmann::json::parse(kYuyvJson);
  json.erase(GetParam());
  make(json.dump());
  EXPECT_EQ(open_error(), json_path() + ": missing required field \"" + GetParam() + "\"");
}

INSTANTIATE_TEST_SUITE_P(RecordingReaderErrors, MissingField,
                         ::testing::Values("pixel_format", "width", "height", "fps"));

TEST_F(RecordingReaderErrors, WrongTypeNamesFieldAndValue) {
  make(R"({"pixel_format": "YUYV", "width": "320", "height": 4, "fps": 30})");
  EXPECT_EQ(open_error(), json_path() + ": \"width\" must be an integer, got \"320\" (string)");
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": "30"})");
  EXPECT_EQ(open_error(), json_path() + ": \"fps\" must be a number, got \"30\" (string)");
  make(R"({"pixel_format": 1, "width": 4, "height": 4, "fps": 30})");
  EXPECT_EQ(open_error(), json_path() + ": \"pixel_format\" must be a string, got 1 (number)");
}

TEST_F(RecordingReaderErrors, OutOfRange) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 0})");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": \"fps\" is out of range: 0"));
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": -30})");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": \"fps\" is out of range: -30"));
  make(R"({"pixel_format": "YUYV", "width": 0, "height": 4, "fps": 30})");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": \"width\" is out of range: 0"));
  make(R"({"pixel_format": "YUYV", "width": 4, "height": -4, "fps": 30})");
  EXPECT_THAT(open_error(), HasSubstr(json_path() + ": \"height\" is out of range: -4"));
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "bytesperline": 6, "fps": 30})");
  EXPECT_EQ(open_error(), json_path() + ": \"bytesperline\" is out of range: 6 is less than width x bytes per "
                                        "pixel = 8 (YUYV 4x4)");
}

TEST_F(RecordingReaderErrors, UnknownPixelFormatListsSupportedOnes) {
  make(R"({"pixel_format": "MJPG", "width": 4, "height": 4, "fps": 30})");
  EXPECT_EQ(open_error(), json_path() + ": \"pixel_format\": unknown pixel format \"MJPG\" (supported: YUYV, GREY)");
  // A line end in the value (JSON's "\n") stays escaped: one line (fuzz
  // finding 14, tests/fuzz/corpus/recording_json/regression-format-line-end.json).
  make(R"({"pixel_format": "YUY\nheight", "width": 4, "height": 4, "fps": 30})");
  EXPECT_EQ(open_error(), json_path() + ": \"pixel_format\": unknown pixel format \"YUY\\nheight\" (supported: YUYV, GREY)");
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30, "streams": {"top\tview": {}}})");
  EXPECT_EQ(open_error(), json_path() + ": \"streams\": unknown stream \"top\\tview\" (expected frontal, lateral)");
}

TEST_F(RecordingReaderErrors, StreamsWhoseFormatsDiffer) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "streams": {"lateral": {"pixel_format": "GREY"}}})");
  EXPECT_EQ(open_error(), json_path() + ": streams whose formats differ: frontal is YUYV 4x4 bpl 8, lateral is "
                                        "GREY 4x4 bpl 4 (both cameras must deliver the same format)");
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "streams": {"frontal": {"bytesperline": 16}}})");
  EXPECT_EQ(open_error(), json_path() + ": streams whose formats differ: frontal is YUYV 4x4 bpl 16, lateral is "
                                        "YUYV 4x4 bpl 8 (both cameras must deliver the same format)");
}

TEST_F(RecordingReaderErrors, StreamsThatAgreeAreAccepted) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "streams": {"frontal": {"pixel_format": "YUYV", "bytesperline": 8}, "lateral": {"height": 4}}})");
  auto reader = RecordingReader::open(dir());
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_EQ(reader->info().format, kYuyv);
}

TEST_F(RecordingReaderErrors, UnknownStreamName) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30, "frames": {"frontl": []}})");
  EXPECT_EQ(open_error(), json_path() + ": \"frames\": unknown stream \"frontl\" (expected frontal, lateral)");
}

TEST_F(RecordingReaderErrors, EmptyStream) {
  make(kYuyvJson, 0);
  EXPECT_EQ(open_error(), frontal_path() + ": empty stream: 0 bytes, not one whole 32-byte frame (YUYV 4x4 bpl 8)");
}

TEST_F(RecordingReaderErrors, FileSmallerThanOneFrameIsAnEmptyStream) {
  make(kYuyvJson, 0);
  append_raw(dir() / "frontal.raw", kYuyv, 0, 0, 20);
  EXPECT_EQ(open_error(), frontal_path() + ": empty stream: 20 bytes, not one whole 32-byte frame (YUYV 4x4 bpl 8)");
}

TEST_F(RecordingReaderErrors, SizeNotAWholeNumberOfListedFrames) {
  // The brief's example: one 320x240 YUYV frame listed, one byte too many.
  const auto format = FrameFormat::packed(PixelFormat::YUYV, 320, 240);
  write_raw_recording(dir(), format, 1,
                      R"({"pixel_format": "YUYV", "width": 320, "height": 240, "fps": 30,
                          "frames": {"frontal": [{"seq": 0, "t_ns": 0}], "lateral": [{"seq": 0, "t_ns": 0}]}})");
  append_raw(dir() / "frontal.raw", format, 0, 0, 1);
  EXPECT_EQ(open_error(), frontal_path() + ": 153601 bytes is not a whole number of 153600-byte frames (" +
                              json_path() + " frames.frontal lists 1 frames)");
}

TEST_F(RecordingReaderErrors, SizeThatFitsTheOtherPixelFormatIsAnError) {
  // 3 GREY 4x4 frames = 48 bytes = 1.5 YUYV frames: a format mix-up, not a truncation.
  make(kYuyvJson, 0);
  append_raw(dir() / "frontal.raw", FrameFormat::packed(PixelFormat::GREY, 4, 4), 3, 0);
  append_raw(dir() / "lateral.raw", kYuyv, 2, 0);
  EXPECT_EQ(open_error(), frontal_path() + ": 48 bytes is not a whole number of 32-byte frames (YUYV 4x4 bpl 8), "
                                           "but exactly 3 frames of GREY 4x4 bpl 4 (16 bytes): check pixel_format "
                                           "and bytesperline in recording.json");
}

TEST_F(RecordingReaderErrors, SizeThatFitsPackedRowsIsAnError) {
  // bytesperline 12 declared (48-byte frames) but the file holds packed 32-byte frames.
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "bytesperline": 12, "fps": 30})", 0);
  append_raw(dir() / "frontal.raw", kYuyv, 3, 0);  // 96 bytes = 2 padded frames: indistinguishable, accepted
  append_raw(dir() / "lateral.raw", kYuyv, 5, 0);  // 160 bytes = 3 padded frames + 16 = 5 packed frames
  EXPECT_THAT(open_error(), HasSubstr((dir() / "lateral.raw").string() +
                                      ": 160 bytes is not a whole number of 48-byte frames (YUYV 4x4 bpl 12), but "
                                      "exactly 5 frames of YUYV 4x4 bpl 8 (32 bytes)"));
}

TEST_F(RecordingReaderErrors, TruncatedLastFrameWithoutMetadataIsDroppedWithAWarning) {
  make(kYuyvJson, 2);
  append_raw(dir() / "lateral.raw", kYuyv, 0, 0, 5);  // 69 bytes: 2 frames and 5 bytes of a third
  auto reader = RecordingReader::open(dir());
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_EQ(reader->frame_count(View::Lateral), 2u);
  EXPECT_EQ(reader->frame_count(View::Frontal), 2u);
  ASSERT_EQ(reader->warnings().size(), 1u);
  EXPECT_EQ(reader->warnings()[0],
            (dir() / "lateral.raw").string() + ": 69 bytes: truncated last frame dropped (5 of 32 bytes)");
  auto last = reader->read(View::Lateral, 1);
  ASSERT_TRUE(last.ok()) << last.error().message;
  EXPECT_EQ(to_vector(last->bytes()), pattern_bytes(32, 1001));
  EXPECT_FALSE(reader->read(View::Lateral, 2).ok());
}

TEST_F(RecordingReaderErrors, TruncatedLastFrameWithMetadataDropsItsEntry) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"frontal": [{"seq": 4, "t_ns": 10}, {"seq": 5, "t_ns": 20}, {"seq": 7, "t_ns": 40}]}})", 2);
  append_raw(dir() / "frontal.raw", kYuyv, 0, 0, 31);
  auto reader = RecordingReader::open(dir());
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  ASSERT_EQ(reader->info().frames[0].size(), 2u);
  EXPECT_EQ(reader->info().frames[0][1].sequence, 5u);
  EXPECT_EQ(reader->info().frames[0][1].timestamp_ns, 20);
  ASSERT_EQ(reader->warnings().size(), 1u);
  EXPECT_THAT(reader->warnings()[0], HasSubstr("frontal.raw: 95 bytes: truncated last frame dropped (31 of 32 bytes)"));
  // The lateral stream has no "frames" entry: index and fps.
  EXPECT_EQ(reader->info().frames[1][1].sequence, 1u);
  EXPECT_EQ(reader->info().frames[1][1].timestamp_ns, 33333333);
}

TEST_F(RecordingReaderErrors, MetadataCountMismatch) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"lateral": [{"seq": 0, "t_ns": 0}, {"seq": 1, "t_ns": 1}, {"seq": 2, "t_ns": 2}]}})", 2);
  EXPECT_EQ(open_error(), (dir() / "lateral.raw").string() + ": holds 2 frames of 32 bytes but " + json_path() +
                              " frames.lateral lists 3 frames");
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"lateral": [{"seq": 0, "t_ns": 0}]}})", 2);
  EXPECT_THAT(open_error(), HasSubstr("holds 2 frames of 32 bytes but"));
}

TEST_F(RecordingReaderErrors, SeqNotStrictlyIncreasing) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"frontal": [{"seq": 3, "t_ns": 0}, {"seq": 3, "t_ns": 5}]}})");
  EXPECT_EQ(open_error(), json_path() + ": \"frames.frontal[1].seq\" is 3, not greater than the previous frame's 3 "
                                        "(seq must increase strictly)");
}

TEST_F(RecordingReaderErrors, TimestampDecreasing) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"lateral": [{"seq": 0, "t_ns": 500}, {"seq": 1, "t_ns": 499}]}})");
  EXPECT_EQ(open_error(), json_path() + ": \"frames.lateral[1].t_ns\" is 499, less than the previous frame's 500 "
                                        "(timestamps must not decrease)");
}

TEST_F(RecordingReaderErrors, MalformedFrameEntries) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30,
           "frames": {"frontal": [{"seq": 0, "t_ns": 0}, {"seq": 1}]}})");
  EXPECT_EQ(open_error(), json_path() + ": \"frames.frontal[1]\": missing field \"t_ns\"");
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30, "frames": {"frontal": [{"seq": -1, "t_ns": 0}]}})");
  EXPECT_THAT(open_error(), HasSubstr(": \"frames.frontal[0].seq\" is out of range: -1"));
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30, "frames": {"frontal": {"seq": 0}}})");
  EXPECT_THAT(open_error(), HasSubstr(": \"frames.frontal\" must be an array, got {\"seq\":0} (object)"));
}

TEST_F(RecordingReaderErrors, NotesMustBeAString) {
  make(R"({"pixel_format": "YUYV", "width": 4, "height": 4, "fps": 30, "notes": 5})");
  EXPECT_EQ(open_error(), json_path() + ": \"notes\" must be a string, got 5 (number)");
}

TEST_F(RecordingReaderErrors, FileShrinkingAfterOpenIsAReadErrorNotACrash) {
  make(kYuyvJson, 2);
  auto reader = RecordingReader::open(dir());
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  std::filesystem::resize_file(dir() / "frontal.raw", 40);
  ASSERT_TRUE(reader->read(View::Frontal, 0).ok());
  auto second = reader->read(View::Frontal, 1);
  ASSERT_FALSE(second.ok());
  EXPECT_THAT(second.error().message, HasSubstr(frontal_path() + ": cannot read frame 1"));
}

}  // namespace
}  // namespace spinewatch::test
