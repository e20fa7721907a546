// What every module shares from frames: the one way an input file is read
// (and its one wording of failure), and the monotonic clock.
#include <gtest/gtest.h>

#include <time.h>

#include "spinewatch/frames/clock.hpp"
#include "spinewatch/frames/text_file.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(TextFile, ReadsTheWholeFileBytesAsTheyAre) {
  test::TempDir dir;
  std::string text(200000, 'x');
  text[7] = '\0';
  text += "\r\nlast line without its end";
  test::write_file(dir.path() / "big.txt", text);
  auto read = read_text_file(dir.path() / "big.txt");
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(*read, text);
}

TEST(TextFile, EveryFailureIsOneMessageWithThePathAndTheReason) {
  test::TempDir dir;
  const auto missing = dir.path() / "missing.toml";
  EXPECT_EQ(read_text_file(missing).error().message, missing.string() + ": cannot open: No such file or directory");
  EXPECT_EQ(read_text_file(dir.path()).error().message, dir.path().string() + ": cannot open: Is a directory");
}

TEST(TextFile, AFileBeyondTheCapIsRefusedNotRead) {
  test::TempDir dir;
  test::write_file(dir.path() / "five.txt", "12345");
  EXPECT_TRUE(read_text_file(dir.path() / "five.txt", 5));
  EXPECT_EQ(read_text_file(dir.path() / "five.txt", 4).error().message,
            (dir.path() / "five.txt").string() + ": larger than 4 bytes, not an input file of spinewatch");
  // A device that never ends stops at the cap.
  EXPECT_FALSE(read_text_file("/dev/zero", 1 << 20));
}

TEST(Clock, MonotonicIsTheKernelsClockMonotonic) {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  const std::int64_t before = std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
  const std::int64_t now = monotonic_now_ns();
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  const std::int64_t after = std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
  EXPECT_LE(before, now);
  EXPECT_LE(now, after);
  // CLOCK_REALTIME is decades ahead of CLOCK_MONOTONIC on any running system.
  EXPECT_GT(realtime_now_ns() - monotonic_now_ns(), std::int64_t{1'000'000'000} * 3600 * 24 * 365);
}

}  // namespace
}  // namespace spinewatch
