// The daemon in-process: Daemon::create and run() on the fake pair source
// with the stand-in estimator, its stream read from the Unix socket, its
// outputs stopped by stop() as by SIGTERM.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/daemon_parts.hpp"
#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/daemon/testing/fake_pair_source.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

Config config_in(const test::TempDir& dir, const std::string& extra = "") {
  const auto path = dir / "spinewatch.toml";
  std::ofstream(path) << "[publish]\nlisten = \"none\"\nunix_socket = \"" << (dir / "sock").string() << "\"\n"
                      << extra;
  auto config = load_config(path);
  EXPECT_TRUE(config) << config.error().message;
  return *config;
}

// An output that records what reaches it, as a new output would.
struct RecordingSink final : PostureSink {
  struct Seen {
    std::mutex mutex;
    std::vector<std::uint64_t> seqs;
    std::vector<std::string> lines, notes;
    int stops = 0;
  };
  explicit RecordingSink(std::shared_ptr<Seen> seen) : seen(std::move(seen)) {}
  std::string_view name() const override { return "recording"; }
  void on_posture(const PostureEvent& e) override {
    std::lock_guard lock(seen->mutex);
    seen->seqs.push_back(e.pair.sequence);
    seen->lines.push_back(e.line);
  }
  void on_note(NoteLevel level, std::string_view message) override {
    std::lock_guard lock(seen->mutex);
    seen->notes.push_back(std::string(to_string(level)) + " " + std::string(message));
  }
  void stop() override {
    std::lock_guard lock(seen->mutex);
    ++seen->stops;
  }
  std::shared_ptr<Seen> seen;
};

TEST(Daemon, RunsInProcessOnAFakeSourceServesTheStreamAndStopsItsOutputs) {
  test::TempDir dir;
  auto seen = std::make_shared<RecordingSink::Seen>();
  DaemonParts parts;
  parts.source = std::make_unique<test::FakePairSource>(test::FakePairSource::Options{.count = 40});
  parts.estimate = test::lost_posture;
  parts.sinks.push_back(std::make_unique<RecordingSink>(seen));
  auto daemon = Daemon::create(dir / "spinewatch.toml", config_in(dir), {}, std::move(parts));
  ASSERT_TRUE(daemon) << daemon.error().message;

  // Connected before the pipeline starts: the client sees every posture.
  auto client = test::LineClient::unix_socket(dir / "sock");
  auto hello = client.read_line();
  ASSERT_TRUE(hello);
  EXPECT_EQ(nlohmann::json::parse(*hello)["class"], "hello");
  int code = -1;
  std::thread runner([&] { code = (*daemon)->run(); });
  std::vector<std::string> stream;
  while (stream.size() < 40) {
    auto line = client.read_line();
    if (!line) break;
    if (nlohmann::json::parse(*line)["class"] == "posture") stream.push_back(*line);
  }
  (*daemon)->stop();
  runner.join();
  EXPECT_EQ(code, 0);

  ASSERT_EQ(stream.size(), 40u);
  for (std::size_t i = 0; i < stream.size(); ++i) {
    const auto j = nlohmann::json::parse(stream[i]);
    EXPECT_EQ(j["seq"], i);
    EXPECT_EQ(j["state"], "lost");
  }
  std::lock_guard lock(seen->mutex);
  // The test's output got the same lines as the stream, with their pairs.
  ASSERT_EQ(seen->lines.size(), 40u);
  EXPECT_EQ(seen->lines, stream);
  for (std::size_t i = 0; i < seen->seqs.size(); ++i) EXPECT_EQ(seen->seqs[i], i);
  // Stopped once, told how the run went just before.
  EXPECT_EQ(seen->stops, 1);
  ASSERT_EQ(seen->notes.size(), 1u);
  EXPECT_EQ(seen->notes[0].rfind("info stopped: ", 0), 0u) << seen->notes[0];
  EXPECT_NE(seen->notes[0].find("40 pairs"), std::string::npos) << seen->notes[0];
}

TEST(Daemon, StopBeforeRunReturnsAtOnce) {
  test::TempDir dir;
  DaemonParts parts;
  parts.source = std::make_unique<test::FakePairSource>(test::FakePairSource::Options{.count = 0});
  parts.estimate = test::lost_posture;
  auto daemon = Daemon::create(dir / "spinewatch.toml", config_in(dir), {}, std::move(parts));
  ASSERT_TRUE(daemon) << daemon.error().message;
  (*daemon)->stop();
  EXPECT_EQ((*daemon)->run(), 0);
}

TEST(Daemon, ABadOutputKeyFailsCreateWithTheKeyNamed) {
  test::TempDir dir;
  DaemonParts parts;
  parts.source = std::make_unique<test::FakePairSource>(test::FakePairSource::Options{.count = 0});
  auto config = config_in(dir);
  config.publish.listen = "nowhere";
  auto daemon = Daemon::create(dir / "spinewatch.toml", config, {}, std::move(parts));
  ASSERT_FALSE(daemon);
  EXPECT_NE(daemon.error().message.find("publish.listen"), std::string::npos) << daemon.error().message;
}

}  // namespace
}  // namespace spinewatch
