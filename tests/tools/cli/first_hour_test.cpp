// What a new user meets first (issue "A new user's first hour"): the
// commands of README's "Using it" block run as written, the demo recording
// is as accurate as docs/accuracy.md says, and each mistake a user makes
// first gets a message that names its fix.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace spinewatch {
namespace {

// Shell-quoted (built by appending: GCC 12 warns falsely on "'" + s + "'").
std::string quoted(const std::filesystem::path& p) {
  std::string q(1, '\'');
  q.append(p.string());
  q.push_back('\'');
  return q;
}
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The ```sh block under "## Using it", read from README.md now, so that the
// README and this test cannot drift apart.
std::vector<std::string> readme_usage_lines() {
  const std::string readme = test::read_file(test::source_path("README.md"));
  const auto section = readme.find("\n## Using it");
  if (section == std::string::npos) return {};
  const auto open = readme.find("```sh\n", section);
  const auto close = readme.find("\n```", open + 6);
  if (open == std::string::npos || close == std::string::npos) return {};
  std::istringstream block(readme.substr(open + 6, close - open - 6));
  std::vector<std::string> lines;
  for (std::string line; std::getline(block, line);)
    if (line.find_first_not_of(' ') != std::string::npos) lines.push_back(line);
  return lines;
}

// Every command of the block, as written, one after the other in a fresh
// directory with only the build's programs put on PATH. The test adds what
// a person does without typing: after a line that starts the daemon in the
// background, it waits until the daemon answers (on publish.listen, the
// port `spinewatch watch` then connects to), and at the end it stops any
// daemon the block left running.
TEST(ReadmeUsing, EveryCommandRunsAsWrittenInATemporaryDirectory) {
  const auto lines = readme_usage_lines();
  ASSERT_GE(lines.size(), 5u) << "README.md has no ```sh block under \"## Using it\"";
  test::TempDir dir;
  const auto cli = std::filesystem::path(test::cli_path()), daemon = std::filesystem::path(test::daemon_path());
  std::ostringstream script;
  script << "set -euo pipefail\n"
         << "export PATH=" << quoted(cli.parent_path()) << ":" << quoted(daemon.parent_path()) << ":\"$PATH\"\n"
         << "export TMPDIR=" << quoted(dir.path()) << " XDG_RUNTIME_DIR=" << quoted(dir.path()) << "\n"
         << "unset SPINEWATCH_ANSUR_DIR\n"
         << "cd " << quoted(dir.path()) << "\n"
         << "trap 'kill $(jobs -p) 2>/dev/null || true' EXIT\n"
         << "answers() { for _ in $(seq 200); do (exec 3<>/dev/tcp/127.0.0.1/$1) 2>/dev/null && return 0; sleep 0.1; "
            "done; echo \"nothing answers on port $1\" >&2; return 1; }\n";
  for (const std::string& line : lines) {
    script << "echo '>>> " << line.substr(0, line.find('#')) << "'\n" << line << "\n";
    const auto code = line.substr(0, line.find('#'));
    if (code.find_last_not_of(' ') != std::string::npos && code[code.find_last_not_of(' ')] == '&') script << "answers 7117\n";
  }
  test::write_file(dir / "using-it.sh", script.str());
  const auto r = test::run_command("bash " + quoted(dir / "using-it.sh") + " < /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.output.substr(r.output.size() > 6000 ? r.output.size() - 6000 : 0);
  // What the block says it makes is there, in the scratch directory it made (mktemp -d under TMPDIR).
  std::filesystem::path scratch;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    if (entry.is_directory() && entry.path().filename().string().rfind("tmp.", 0) == 0) scratch = entry.path();
  ASSERT_FALSE(scratch.empty()) << "no scratch directory made\n" << r.output.substr(0, 3000);
  for (const char* made : {"flexion/ground_truth.ndjson", "flexion.ndjson", "s.ndjson", "report/report.html",
                           "report/summaries.csv", "opensim/spine.mot", "opensim/spine.trc", "spinewatch.toml"})
    EXPECT_TRUE(std::filesystem::exists(scratch / made)) << made << " was not written";
  EXPECT_TRUE(contains(r.output, "vertebrae")) << "eval printed no errors";
  // 30 postures watched: lines with a latency.
  std::size_t watched = 0;
  std::istringstream out(r.output);
  for (std::string line; std::getline(out, line);) watched += contains(line, " neck ") && contains(line, " latency ");
  EXPECT_EQ(watched, 30u) << r.output.substr(0, 6000);
  // The daemon's stop line gives the run's mean rate, not the last second's 0.0.
  std::smatch stop;
  ASSERT_TRUE(std::regex_search(r.output, stop, std::regex(R"(over the run: ([0-9.]+) pairs/s, ([0-9]+) pairs)")))
      << r.output.substr(r.output.size() > 3000 ? r.output.size() - 3000 : 0);
  EXPECT_GT(std::stod(stop[1]), 5.0) << stop[0];
  // A recording of a few seconds reports seconds, not "0.0 min" everywhere.
  const std::string report = test::read_file(scratch / "report/report.html");
  EXPECT_EQ(report.find(">0.0 min<"), std::string::npos);
  EXPECT_TRUE(std::regex_search(report, std::regex(R"(>[0-9]+\.[0-9] s[ <])"))) << "no time in seconds in the report";
}

// The demo's recording (the embedded default, rendered at build time with
// the phantom's default subject, a measured adult) scored by eval, with
// nothing given: within the accuracy docs/accuracy.md states for measured
// adults (every vertebra 16.9 mm on average).
TEST(DemoRecording, EvalIsWithinTheStatedAccuracy) {
  const auto demo = std::filesystem::path(test::binary_dir()) / "share/spinewatch/demo";
  ASSERT_TRUE(std::filesystem::exists(demo / "ground_truth.ndjson")) << demo;
  const auto recording = nlohmann::json::parse(test::read_file(demo / "recording.json"));
  EXPECT_EQ(recording["subject"].value("name", ""), "ansur:15936") << "the demo is not the measured adult";
  const auto r = test::run_cli("--log-level warn eval --json --recording " + quoted(demo));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto e = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  const double vertebrae = e["vertebrae"]["mean"].get<double>();
  std::printf("demo recording: every vertebra %.1f mm, neck %.1f, waist %.1f\n", vertebrae,
              e["neck"]["mean"].get<double>(), e["waist"]["mean"].get<double>());
  EXPECT_LE(vertebrae, 16.9) << r.output;
  EXPECT_EQ(e["lost_frames"].get<int>(), 0) << r.output;
}

class FirstMistakes : public ::testing::Test {
 protected:
  // A one-pair phantom recording (the generic subject: fastest to render).
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const auto r = test::run_cli("--log-level warn phantom --subject generic --scenario upright --frames 2 --empty-frames 0 "
                                 "--out " + quoted(rec()));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::filesystem::path rec() { return dir_->path() / "rec"; }
  static test::TempDir* dir_;
};
test::TempDir* FirstMistakes::dir_ = nullptr;

TEST_F(FirstMistakes, EvalWithoutGroundTruthSaysItIsNotAPhantomRecording) {
  test::TempDir dir;
  std::filesystem::copy(rec(), dir / "rec");
  std::filesystem::remove(dir / "rec" / "ground_truth.ndjson");
  const auto r = test::run_cli("eval --recording " + quoted(dir / "rec"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "has no ground_truth.ndjson: it is not a phantom recording")) << r.output;
  EXPECT_TRUE(contains(r.output, "--truth FILE")) << r.output;
}

TEST_F(FirstMistakes, ARecordingWithoutCalibrationWarnsAndSaysWhatTheDefaultRigIs) {
  test::TempDir dir;
  std::filesystem::copy(rec(), dir / "rec");
  std::filesystem::remove(dir / "rec" / "calibration.yaml");
  const auto r = test::run_cli("replay --recording " + quoted(dir / "rec") + " --out " + quoted(dir / "p.ndjson"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "warning")) << r.output;
  EXPECT_TRUE(contains(r.output, "no calibration.yaml: replaying on the default rig (two ideal orthogonal cameras 2 m "
                                 "from the subject"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "--calibration")) << r.output;
}

TEST_F(FirstMistakes, ASummariesFileGivenAsTheEstimateIsNamedAsOne) {
  test::TempDir dir;
  const auto summaries = dir / "s.ndjson";
  const auto r0 = test::run_cli("--log-level warn replay --recording " + quoted(rec()) + " --out " +
                                quoted(dir / "p.ndjson") + " --summaries " + quoted(summaries));
  ASSERT_EQ(r0.exit_code, 0) << r0.output;
  ASSERT_TRUE(contains(test::read_file(summaries), "\"class\":\"summary\"")) << test::read_file(summaries);
  const auto r = test::run_cli("eval --recording " + quoted(rec()) + " --estimate " + quoted(summaries));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "s.ndjson:1: an exposure summary line: this is a summaries file")) << r.output;
  EXPECT_TRUE(contains(r.output, "the file replay --out wrote")) << r.output;
}

TEST(FirstMistake, WatchWithNoDaemonNamesTheAddressAndThatTheDaemonIsNotRunning) {
  const std::string address = "127.0.0.1:" + std::to_string(test::free_port());
  const auto r = test::run_cli("watch --connect " + address + " --count 1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "watch: " + address + ": Connection refused: the daemon is not running there"))
      << r.output;
  test::TempDir dir;
  const auto unix = test::run_cli("watch --unix " + quoted(dir / "none.sock") + " --count 1");
  EXPECT_EQ(unix.exit_code, 1);
  EXPECT_TRUE(contains(unix.output, "the daemon is not running there")) << unix.output;
}

TEST(FirstMistake, AnUnknownConfigKeyNamesTheNearestKnownOne) {
  test::TempDir dir;
  // A name near no key gets no guess.
  test::write_file(dir / "s.toml", "[cameras]\nframerate = 30\n");
  const auto r = test::run_cli("check --config " + quoted(dir / "s.toml"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "s.toml:2: cameras.framerate: unknown key")) << r.output;
  EXPECT_FALSE(contains(r.output, "did you mean")) << r.output;
  test::write_file(dir / "s.toml", "[publish]\nunix_sockt = \"none\"\n");
  const auto typo = test::run_cli("check --config " + quoted(dir / "s.toml"));
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_TRUE(contains(typo.output, "s.toml:2: publish.unix_sockt: unknown key; did you mean publish.unix_socket?"))
      << typo.output;
}

TEST(FirstMistake, NoConfigSaysHowToGetTheAnnotatedOne) {
  if (std::filesystem::exists("/etc/spinewatch/spinewatch.toml")) GTEST_SKIP() << "a station is installed here";
  const auto r = test::run_command(test::daemon_path() + " 2>&1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "/etc/spinewatch/spinewatch.toml: no such file; give --config FILE")) << r.output;
  EXPECT_TRUE(contains(r.output, "spinewatchd --print-config > spinewatch.toml")) << r.output;
  EXPECT_TRUE(contains(r.output, "config/spinewatch.toml")) << r.output;
  // What it prints is the annotated file, and a configuration the daemon accepts.
  test::TempDir dir;
  const auto printed = test::run_command(test::daemon_path() + " --print-config > " + quoted(dir / "s.toml"));
  ASSERT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_EQ(test::read_file(dir / "s.toml"), test::read_file(test::source_path("config/spinewatch.toml")));
  EXPECT_EQ(test::run_cli("check --config " + quoted(dir / "s.toml")).exit_code, 0);
}

TEST(FirstMistake, AnAnsurSubjectOutsideTheCloneNamesTheVariable) {
  test::TempDir dir;
  const auto r = test::run_command("cd " + quoted(dir.path()) + " && env -u SPINEWATCH_ANSUR_DIR " + test::cli_path() +
                                   " phantom --scenario upright --subject ansur:15936 --out rec 2>&1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, "set $SPINEWATCH_ANSUR_DIR to the directory holding ANSUR_II_MALE_Public.csv"))
      << r.output;
}

// libcamera's "No IPA found" (no image-processing modules installed) is no
// warning for a user listing devices: it is said once, in words, at info.
TEST(Cli, DevicesPrintsNoLibcameraWarningAboutIpaModules) {
  const auto r = test::run_cli("devices");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(contains(r.output, "WARN IPAManager")) << r.output;
  EXPECT_FALSE(contains(r.output, "No IPA found")) << r.output;
}

TEST(Cli, HelpGroupsTheStationsCommandsApartFromResearchOnes) {
  const auto r = test::run_cli("--help");
  ASSERT_EQ(r.exit_code, 0);
  const auto station = r.output.find("\nStation:"), testing = r.output.find("\nTesting"),
             research = r.output.find("\nResearch and development");
  ASSERT_NE(station, std::string::npos) << r.output;
  ASSERT_NE(research, std::string::npos) << r.output;
  EXPECT_LT(station, testing);
  EXPECT_LT(testing, research);
  for (const char* command : {"replay", "watch", "record", "report", "calibrate"}) {
    const auto at = r.output.find("\n  " + std::string(command) + " ");
    EXPECT_TRUE(at > station && at < testing) << command << "\n" << r.output;
  }
  for (const char* command : {"fit-spine", "fit-cvsm", "fit-anthropometry", "population", "deform"}) {
    const auto at = r.output.find("\n  " + std::string(command) + " ");
    EXPECT_TRUE(at != std::string::npos && at > research) << command << "\n" << r.output;
  }
}

}  // namespace
}  // namespace spinewatch
