// RecordingSource: merge order, fast and paced delivery, looping, stop().

#include <chrono>
#include <map>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "recording_fixtures.hpp"
#include "spinewatch/capture/recording_source.hpp"
#include "spinewatch/frames/clock.hpp"
#include "test_support.hpp"

namespace spinewatch::test {
namespace {

const FrameFormat kGrey = FrameFormat::packed(PixelFormat::GREY, 8, 4);

// Seeds identify frames: frontal frame i has seed 100 + i, lateral 200 + i.
std::uint32_t seed_of(View view, std::size_t i) {
  return (view == View::Frontal ? 100u : 200u) + static_cast<std::uint32_t>(i);
}

void write_timed_recording(const std::filesystem::path& dir, double fps, const std::vector<FrameInfo>& frontal,
                           const std::vector<FrameInfo>& lateral) {
  auto writer = RecordingWriter::create(dir, kGrey, fps);
  ASSERT_TRUE(writer.ok()) << writer.error().message;
  for (std::size_t i = 0; i < frontal.size(); ++i)
    ASSERT_TRUE(writer->write(View::Frontal, pattern_frame(kGrey, frontal[i], seed_of(View::Frontal, i))).ok());
  for (std::size_t i = 0; i < lateral.size(); ++i)
    ASSERT_TRUE(writer->write(View::Lateral, pattern_frame(kGrey, lateral[i], seed_of(View::Lateral, i))).ok());
  ASSERT_TRUE(writer->finish().ok());
}

// Which recorded frame a delivered frame is, found by its bytes.
std::size_t identify(const SourcedFrame& f, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i)
    if (to_vector(f.frame.bytes()) == pattern_bytes(kGrey.frame_bytes(), seed_of(f.view, i))) return i;
  ADD_FAILURE() << "delivered bytes match no recorded " << to_string(f.view) << " frame";
  return count;
}

RecordingSource open_source(const std::filesystem::path& dir, RecordingSourceOptions options) {
  auto source = RecordingSource::open(dir, options);
  EXPECT_TRUE(source.ok()) << source.error().message;
  return std::move(*source);
}

// 30 fps cameras half a period apart; lateral dropped its last frame.
const std::vector<FrameInfo> kFrontal = {{10, 1'000'000'000}, {11, 1'033'333'333}, {12, 1'066'666'667},
                                         {13, 1'100'000'000}};
const std::vector<FrameInfo> kLateral = {{50, 1'016'000'000}, {51, 1'049'000'000}, {53, 1'083'000'000}};

TEST(RecordingSource, FastModeMergesByTimestampAndKeepsRecordedMetadata) {
  TempDir tmp;
  write_timed_recording(tmp / "rec", 30, kFrontal, kLateral);
  auto source = open_source(tmp / "rec", {});

  std::vector<std::pair<View, std::size_t>> order;
  while (auto f = source.next()) {
    const auto i = identify(*f, f->view == View::Frontal ? kFrontal.size() : kLateral.size());
    ASSERT_LT(i, 4u);
    const auto& recorded = (f->view == View::Frontal ? kFrontal : kLateral)[i];
    EXPECT_EQ(f->frame.sequence(), recorded.sequence);
    EXPECT_EQ(f->frame.timestamp_ns(), recorded.timestamp_ns);
    EXPECT_EQ(f->frame.format(), kGrey);
    order.emplace_back(f->view, i);
  }
  const std::vector<std::pair<View, std::size_t>> expected = {
      {View::Frontal, 0}, {View::Lateral, 0}, {View::Frontal, 1}, {View::Lateral, 1},
      {View::Frontal, 2}, {View::Lateral, 2}, {View::Frontal, 3}};
  EXPECT_EQ(order, expected);
  EXPECT_FALSE(source.next().has_value()) << "the end stays the end";
  EXPECT_FALSE(source.error().has_value());
}

TEST(RecordingSource, EqualTimestampsGiveFrontalFirst) {
  TempDir tmp;
  const std::vector<FrameInfo> same = {{0, 0}, {1, 100}};
  write_timed_recording(tmp / "rec", 30, same, same);
  auto source = open_source(tmp / "rec", {});
  std::vector<View> views;
  while (auto f = source.next()) views.push_back(f->view);
  EXPECT_EQ(views, (std::vector<View>{View::Frontal, View::Lateral, View::Frontal, View::Lateral}));
}

TEST(RecordingSource, LoopKeepsSeqAndTimeIncreasingAndPairsAcrossTheWrap) {
  TempDir tmp;
  // Both cameras share seq and t per exposure; lateral lost exposure 3.
  const std::vector<FrameInfo> frontal = {{0, 0}, {1, 100'000'000}, {2, 200'000'000}, {3, 300'000'000}};
  const std::vector<FrameInfo> lateral = {{0, 0}, {1, 100'000'000}, {2, 200'000'000}};
  write_timed_recording(tmp / "rec", 10, frontal, lateral);
  auto source = open_source(tmp / "rec", {.paced = false, .loop = true});

  std::map<View, FrameInfo> last;
  std::map<std::uint64_t, std::int64_t> t_of_seq[2];
  std::size_t wraps[2] = {0, 0};
  for (int n = 0; n < 7 * 3; ++n) {  // three laps
    auto f = source.next();
    ASSERT_TRUE(f.has_value()) << "a looping source never ends";
    const auto info = f->frame.info();
    const auto i = identify(*f, 4);
    if (auto prev = last.find(f->view); prev != last.end()) {
      EXPECT_GT(info.sequence, prev->second.sequence) << to_string(f->view) << " frame " << n;
      EXPECT_GT(info.timestamp_ns, prev->second.timestamp_ns) << to_string(f->view) << " frame " << n;
      if (i == 0) ++wraps[static_cast<int>(f->view)];
    }
    last[f->view] = info;
    t_of_seq[static_cast<int>(f->view)][info.sequence] = info.timestamp_ns;
  }
  EXPECT_EQ(wraps[0], 2u);
  EXPECT_EQ(wraps[1], 2u);
  // The first frame of lap 1: seq + (largest seq + 1), t + (length + one period).
  EXPECT_EQ(t_of_seq[0].at(4), 400'000'000);
  EXPECT_EQ(t_of_seq[1].at(4), 400'000'000);
  // Frames of the same exposure keep the same seq and t on every lap.
  std::size_t pairs = 0;
  for (const auto& [seq, t] : t_of_seq[1]) {
    auto frontal_t = t_of_seq[0].find(seq);
    ASSERT_NE(frontal_t, t_of_seq[0].end()) << "lateral seq " << seq << " has no frontal partner";
    EXPECT_EQ(frontal_t->second, t);
    ++pairs;
  }
  EXPECT_EQ(pairs, 9u);
}

TEST(RecordingSource, PacedDeliversNoEarlierThanScheduledWithMonotonicTimestamps) {
  TempDir tmp;
  std::vector<FrameInfo> frontal, lateral;
  for (int i = 0; i < 5; ++i) {
    frontal.push_back({static_cast<std::uint64_t>(i), 5'000'000'000 + i * 20'000'000});
    lateral.push_back({static_cast<std::uint64_t>(i), 5'000'000'000 + i * 20'000'000 + 10'000'000});
  }
  write_timed_recording(tmp / "rec", 50, frontal, lateral);
  auto source = open_source(tmp / "rec", {.paced = true, .loop = false});

  const auto before = monotonic_now_ns();
  std::optional<std::int64_t> first_t;
  int delivered = 0;
  while (auto f = source.next()) {
    const auto now = monotonic_now_ns();
    const auto t = f->frame.timestamp_ns();
    if (!first_t) first_t = t;
    const auto i = identify(*f, 5);
    const auto recorded = (f->view == View::Frontal ? frontal : lateral)[i].timestamp_ns;
    EXPECT_EQ(t - *first_t, recorded - 5'000'000'000) << "rebased: start + (t_rec - t_rec_first)";
    EXPECT_GE(now, t) << "delivered before its time";
    ++delivered;
  }
  EXPECT_EQ(delivered, 10);
  ASSERT_TRUE(first_t.has_value());
  EXPECT_GE(*first_t, before) << "timestamps are CLOCK_MONOTONIC of this run";
  const auto elapsed = monotonic_now_ns() - before;
  EXPECT_GE(elapsed, 90'000'000);
  EXPECT_LT(elapsed, 5'000'000'000) << "loose upper bound only";
}

TEST(RecordingSource, StopFromAnotherThreadWakesAPacedNext) {
  TempDir tmp;
  // The second frame is due 30 s after the first.
  write_timed_recording(tmp / "rec", 30, {{0, 0}, {1, 30'000'000'000}}, {{0, 0}});
  auto source = open_source(tmp / "rec", {.paced = true, .loop = true});
  ASSERT_TRUE(source.next().has_value());
  ASSERT_TRUE(source.next().has_value());

  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    source.stop();
  });
  const auto before = monotonic_now_ns();
  const auto waited = source.next();
  const auto after = monotonic_now_ns();
  stopper.join();
  EXPECT_FALSE(waited.has_value());
  EXPECT_LT(after - before, 2'000'000'000) << "stop() must wake the sleeping next()";
  EXPECT_FALSE(source.next().has_value()) << "stopped stays stopped";
}

TEST(RecordingSource, ReadErrorEndsTheSourceWithTheError) {
  TempDir tmp;
  write_timed_recording(tmp / "rec", 30, kFrontal, kLateral);
  auto source = open_source(tmp / "rec", {});
  std::filesystem::resize_file(tmp / "rec" / "lateral.raw", 0);
  ASSERT_TRUE(source.next().has_value());  // frontal 0
  EXPECT_FALSE(source.next().has_value());
  ASSERT_TRUE(source.error().has_value());
  EXPECT_THAT(source.error()->message, ::testing::HasSubstr("lateral.raw: cannot read frame 0"));
}

TEST(RecordingSource, OpenReportsTheReaderError) {
  TempDir tmp;
  auto source = RecordingSource::open(tmp / "nothing", {});
  ASSERT_FALSE(source.ok());
  EXPECT_EQ(source.error().message, (tmp / "nothing").string() + ": no such recording directory");
}

}  // namespace
}  // namespace spinewatch::test
