// The spinewatch CLI on real devices: record both vivid cameras, replay the result.
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "driver_query.hpp"
#include "guest_env.hpp"
#include "largest_pairing.hpp"
#include "spinewatch/capture/recording.hpp"
#include "spinewatch/estimator/posture_json.hpp"

namespace spinewatch::kernel_test {
namespace {

namespace fs = std::filesystem;

struct CommandRun {
  int exit_code = -1;
  std::string output;
};

CommandRun run_command(const std::string& command) {
  CommandRun r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> chunk{};
  while (std::fgets(chunk.data(), chunk.size(), pipe)) r.output += chunk.data();
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(CLI, RecordReplay) {
  SW_REQUIRE_ENV("SW_V4L2_SKIP", "SW_VIDEO_A", "SW_VIDEO_B", "SW_CLI", "SW_TMP");
  constexpr int kFrames = 12;
  const fs::path dir = fs::path(env_or_empty("SW_TMP")) / "cli-recording";
  fs::remove_all(dir);
  const std::string cli = env_or_empty("SW_CLI");
  const CommandRun record = run_command(cli + " record --out " + dir.string() + " --frontal " + env_or_empty("SW_VIDEO_A") +
                         " --lateral " + env_or_empty("SW_VIDEO_B") + " --frames " + std::to_string(kFrames));
  ASSERT_EQ(record.exit_code, 0) << record.output;

  auto reader = RecordingReader::open(dir);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_EQ(reader->info().format, (FrameFormat{PixelFormat::YUYV, 320, 240, 640}));
  const auto fps = driver_fps(env_or_empty("SW_VIDEO_A"));
  ASSERT_TRUE(fps);
  EXPECT_DOUBLE_EQ(reader->info().fps, *fps);  // what the driver runs at, not what was asked
  for (View v : kViews) {
    SCOPED_TRACE(std::string(to_string(v)));
    ASSERT_EQ(reader->frame_count(v), static_cast<std::size_t>(kFrames));
    const auto& frames = reader->info().frames[static_cast<int>(v)];
    for (std::size_t i = 1; i < frames.size(); ++i) {
      EXPECT_GT(frames[i].sequence, frames[i - 1].sequence);
      EXPECT_GT(frames[i].timestamp_ns, frames[i - 1].timestamp_ns);
    }
  }
  EXPECT_TRUE(fs::exists(dir / "calibration.yaml"));

  const fs::path out = dir / "postures.ndjson";
  const CommandRun replay = run_command(cli + " replay --recording " + dir.string() + " --out " + out.string());
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  std::ifstream in(out);
  std::set<std::uint64_t> frontal_sequences;
  for (const auto& f : reader->info().frames[0]) frontal_sequences.insert(f.sequence);
  std::string line;
  int lines = 0;
  std::optional<std::uint64_t> last_seq;
  while (std::getline(in, line)) {
    auto posture = decode_posture(line, out.string() + ":" + std::to_string(lines + 1));
    ASSERT_TRUE(posture.ok()) << posture.error().message;
    // In replay, seq is the pair's sequence number in the recording (docs/interfaces.md §3).
    EXPECT_TRUE(frontal_sequences.count(posture->seq)) << "line " << lines + 1 << ": seq " << posture->seq;
    if (last_seq) {
      EXPECT_GT(posture->seq, *last_seq) << "line " << lines + 1;
    }
    last_seq = posture->seq;
    ++lines;
  }
  // Two free-running cameras pair frame for frame, give or take the ends;
  // which frames pair depends on how the guest scheduled the two capture
  // threads (a loaded host starts one camera late, or bunches a camera's
  // frames), so the expected count comes from the recorded timestamps.
  const std::int64_t tolerance_ns = std::llround(1e9 / *fps) / 2;  // the pairer's: half a period
  std::vector<std::int64_t> times[2];
  std::string timestamps;
  for (View v : kViews)
    for (const auto& frame : reader->info().frames[static_cast<int>(v)]) {
      times[static_cast<int>(v)].push_back(frame.timestamp_ns);
      timestamps += std::string(to_string(v)) + " " + std::to_string(frame.timestamp_ns) + "\n";
    }
  const auto matchable = static_cast<int>(largest_pairing(times[0], times[1], tolerance_ns));
  EXPECT_EQ(lines, matchable) << "recorded timestamps:\n" << timestamps << replay.output;
  EXPECT_GE(lines, kFrames / 2);
  EXPECT_LE(lines, kFrames);
}

}  // namespace
}  // namespace spinewatch::kernel_test
