// A new output, added the way docs/architecture.md says: one PostureSink
// (here a CSV file of seq, t_ns, state per posture) and one line where the
// outputs are listed — for a test, DaemonParts::sinks. Nothing else in the
// daemon changes.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "app/daemon_parts.hpp"
#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/daemon/testing/fake_pair_source.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

class CsvSink final : public PostureSink {
 public:
  explicit CsvSink(const std::filesystem::path& path) : out_(path) { out_ << "seq,t_ns,state\n"; }
  std::string_view name() const override { return "csv"; }
  void on_posture(const PostureEvent& e) override {
    out_ << e.posture.seq << ',' << e.posture.t_ns << ',' << to_string(e.posture.state) << '\n';
    ++rows_;
  }
  void add_status(std::string& text) const override { text += "; csv " + std::to_string(rows_.load()) + " rows"; }
  void stop() override { out_.close(); }

 private:
  std::ofstream out_;
  std::atomic<std::uint64_t> rows_{0};
};

std::vector<std::string> lines_of(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(CsvSink, ANewOutputGetsEveryPostureAndIsClosedAtTheStop) {
  test::TempDir dir;
  std::ofstream(dir / "spinewatch.toml") << "[publish]\nlisten = \"none\"\nunix_socket = \""
                                         << (dir / "sock").string() << "\"\n";
  auto config = load_config(dir / "spinewatch.toml");
  ASSERT_TRUE(config) << config.error().message;
  DaemonParts parts;
  parts.source = std::make_unique<test::FakePairSource>(test::FakePairSource::Options{.count = 25});
  parts.estimate = test::lost_posture;
  parts.sinks.push_back(std::make_unique<CsvSink>(dir / "postures.csv"));
  auto daemon = Daemon::create(dir / "spinewatch.toml", *config, {}, std::move(parts));
  ASSERT_TRUE(daemon) << daemon.error().message;
  // Connected before the pipeline starts, the stream's client sees every
  // posture; the stop then lets the estimator thread finish handing out the
  // last one before any output stops. The hello line says the publisher has
  // taken the client in: connecting alone does not (the accept runs on the
  // network thread, and on a loaded machine the fake source's 25 pairs were
  // all published before it, so the client never saw the last).
  auto client = test::LineClient::unix_socket(dir / "sock");
  const auto hello = client.read_line();
  ASSERT_TRUE(hello && hello->find("\"class\":\"hello\"") != std::string::npos);
  std::thread runner([&] { (*daemon)->run(); });
  bool last_seen = false;
  while (auto line = client.read_line())
    if (line->find("\"class\":\"posture\",\"v\":1,\"seq\":24,") != std::string::npos) {
      last_seen = true;
      break;
    }
  (*daemon)->stop();
  runner.join();
  ASSERT_TRUE(last_seen);

  const auto rows = lines_of(dir / "postures.csv");
  ASSERT_EQ(rows.size(), 26u);
  EXPECT_EQ(rows[0], "seq,t_ns,state");
  EXPECT_EQ(rows[1], "0,1000000000,lost");
  EXPECT_EQ(rows[25], "24,1799999992,lost");  // 1 s + 24 × 33 333 333 ns (the fake source's times)
}

}  // namespace
}  // namespace spinewatch
