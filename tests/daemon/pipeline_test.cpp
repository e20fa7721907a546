#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "pipeline/pipeline.hpp"
#include "publish/publisher.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/daemon/testing/fake_pair_source.hpp"
#include "test_client.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;
using test::FakePairSource;

struct Collected {
  std::mutex mutex;
  std::vector<Posture> postures;
  void add(const Posture& p) {
    std::lock_guard lock(mutex);
    postures.push_back(p);
  }
  std::size_t size() {
    std::lock_guard lock(mutex);
    return postures.size();
  }
};

TEST(Pipeline, SeqCountsPairsSinceStartAcrossALoopingSource) {
  Collected out;
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = 300, .lap = 90}),
                    test::lost_posture, [&](const Posture& p, const FramePair&) { out.add(p); }, {.pair_queue = 4, .lossless = true});
  pipeline.start();
  ASSERT_TRUE(test::eventually([&] { return out.size() == 300; }));
  pipeline.stop();
  for (std::size_t i = 0; i < out.postures.size(); ++i) {
    EXPECT_EQ(out.postures[i].seq, i) << "seq must not restart with the source's own numbering";
    EXPECT_EQ(out.postures[i].t_ns, static_cast<std::int64_t>(1'000'000'000 + i * 33'333'333));
  }
  EXPECT_EQ(pipeline.stats().pairs, 300u);
  EXPECT_EQ(pipeline.stats().pairs_dropped, 0u);
  EXPECT_EQ(pipeline.stats().source.frames, 600u);
}

TEST(Pipeline, SlowEstimatorDropsTheOldestPairsAndCountsThem) {
  Collected out;
  auto slow = [](const FramePair& pair) {
    std::this_thread::sleep_for(2ms);
    return test::lost_posture(pair);
  };
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = 200}), slow,
                    [&](const Posture& p, const FramePair&) { out.add(p); }, {.pair_queue = 4});
  pipeline.start();
  ASSERT_TRUE(test::eventually([&] { return pipeline.stats().pairs == 200 && pipeline.stats().pairs_processed +
                                                                                 pipeline.stats().pairs_dropped == 200; }));
  pipeline.stop();
  const auto s = pipeline.stats();
  EXPECT_GT(s.pairs_dropped, 0u);
  EXPECT_EQ(s.pairs_processed + s.pairs_dropped, 200u);
  ASSERT_EQ(out.postures.size(), s.pairs_processed);
  for (std::size_t i = 1; i < out.postures.size(); ++i) EXPECT_GT(out.postures[i].seq, out.postures[i - 1].seq);
  EXPECT_EQ(out.postures.back().seq, 199u) << "the newest pair is never the one dropped";
}

TEST(Pipeline, StopReturnsPromptlyWhileTheSourceWaits) {
  Collected out;
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = 5}), test::lost_posture,
                    [&](const Posture& p, const FramePair&) { out.add(p); }, {.lossless = true});
  pipeline.start();
  ASSERT_TRUE(test::eventually([&] { return out.size() == 5; }));
  std::this_thread::sleep_for(20ms);
  EXPECT_FALSE(pipeline.source_finished()) << "the fake source waits for stop() after its pairs";
  const auto t0 = std::chrono::steady_clock::now();
  pipeline.stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 500ms);
  EXPECT_TRUE(pipeline.source_finished());
  EXPECT_EQ(out.size(), 5u);
}

TEST(Pipeline, AnEstimatorExceptionBecomesALostPosture) {
  Collected out;
  auto faulty = [](const FramePair& pair) -> Posture {
    if (pair.sequence == 2) throw std::runtime_error("singular matrix");
    Posture p = test::lost_posture(pair);
    p.state = TrackingState::Init;
    return p;
  };
  spdlog::set_level(spdlog::level::off);
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = 4}), faulty,
                    [&](const Posture& p, const FramePair&) { out.add(p); }, {.lossless = true});
  pipeline.start();
  ASSERT_TRUE(test::eventually([&] { return out.size() == 4; }));
  pipeline.stop();
  spdlog::set_level(spdlog::level::info);
  EXPECT_EQ(out.postures[2].state, TrackingState::Lost);
  EXPECT_EQ(out.postures[2].seq, 2u);
  EXPECT_EQ(out.postures[2].fit.flag, "estimator_error");
  EXPECT_EQ(out.postures[3].state, TrackingState::Init);
}

TEST(Pipeline, ACameraLossIsOneLostLineFlaggedCameraLostThatTheEstimatorNeverSees) {
  Collected out;
  std::atomic<int> estimated{0};
  auto counting = [&](const FramePair& pair) {
    EXPECT_FALSE(pair.camera_lost);
    ++estimated;
    return test::lost_posture(pair);
  };
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = 6, .camera_lost_at = 3}),
                    counting, [&](const Posture& p, const FramePair&) { out.add(p); }, {.lossless = true});
  pipeline.start();
  ASSERT_TRUE(test::eventually([&] { return out.size() == 7; }));
  pipeline.stop();
  EXPECT_EQ(estimated.load(), 6);
  for (std::size_t i = 0; i < out.postures.size(); ++i) EXPECT_EQ(out.postures[i].seq, i);
  const Posture& gap = out.postures[3];
  EXPECT_EQ(gap.state, TrackingState::Lost);
  EXPECT_EQ(gap.fit.flag, "camera_lost");
  EXPECT_FALSE(gap.vertebrae);
  EXPECT_GT(gap.t_ns, out.postures[2].t_ns);
  EXPECT_LT(gap.t_ns, out.postures[4].t_ns);
  EXPECT_EQ(pipeline.stats().pairs, 6u);  // the marker is not a pair
}

TEST(BoundedQueue, DropsOldestWhenFull) {
  BoundedQueue<int> q(2);
  EXPECT_FALSE(q.push(1));
  EXPECT_FALSE(q.push(2));
  EXPECT_TRUE(q.push(3));
  EXPECT_EQ(q.pop(), 2);
  EXPECT_EQ(q.pop(), 3);
  q.close();
  EXPECT_EQ(q.pop(), std::nullopt);
}

long vm_rss_kb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// 10 000 pairs of full-size frames through pipeline, encoder and publisher
// to a reading client: memory must stay flat (bounded queues, frames freed).
TEST(PipelineMemory, RssStaysFlatOverTenThousandPairs) {
  spdlog::set_level(spdlog::level::warn);
  test::TempDir dir;
  PublisherOptions options;
  options.tcp = TcpEndpoint{"127.0.0.1", 0};
  options.client_queue = 100000;  // a reader that lags under a sanitizer is not the subject here
  auto publisher = Publisher::start(options, R"({"class":"hello","v":1,"daemon_version":"t","station":"s"})");
  ASSERT_TRUE(publisher.ok()) << publisher.error().message;
  auto client = test::LineClient::tcp((*publisher)->tcp_port());
  ASSERT_TRUE(client.read_line());
  std::atomic<std::uint64_t> received{0};
  // Joined on every path (a failed assertion returns early): the read ends
  // when the publisher stops or after 10 s without a line.
  std::jthread reader([&] {
    while (client.read_line(10s)) ++received;
  });

  constexpr std::uint64_t kPairs = 10'000;
  long rss_at_1000 = 0, rss_at_10000 = 0;
  Pipeline pipeline(std::make_unique<FakePairSource>(FakePairSource::Options{.count = kPairs}), test::lost_posture,
                    [&](const Posture& p, const FramePair&) {
                      (*publisher)->publish(encode_posture_line(p, StreamStats{p.seq + 1, 0, 0, 1, 0}));
                      if (p.seq + 1 == 1000) rss_at_1000 = vm_rss_kb();
                      if (p.seq + 1 == kPairs) rss_at_10000 = vm_rss_kb();
                    },
                    {.pair_queue = 4, .lossless = true});
  pipeline.start();
  // The publisher's inbox drops its oldest line when the I/O thread falls
  // behind (a loaded CI machine did, by 1 649 lines): every line is either
  // received or counted as dropped, and the subject here is memory.
  const auto accounted = [&] { return received.load() + (*publisher)->stats().lines_dropped; };
  ASSERT_TRUE(test::eventually([&] { return accounted() == kPairs; }, 60s))
      << received.load() << " lines received, " << (*publisher)->stats().lines_dropped << " dropped";
  pipeline.stop();
  (*publisher)->stop();
  reader.join();
  EXPECT_GT(received.load(), kPairs / 2);
  spdlog::set_level(spdlog::level::info);
  RecordProperty("rss_kb_at_1000", static_cast<int>(rss_at_1000));
  RecordProperty("rss_kb_at_10000", static_cast<int>(rss_at_10000));
  std::printf("VmRSS after 1000 pairs: %ld kB, after 10000 pairs: %ld kB (%llu lines dropped from the inbox)\n",
              rss_at_1000, rss_at_10000, static_cast<unsigned long long>((*publisher)->stats().lines_dropped));
  ASSERT_GT(rss_at_1000, 0);
#if defined(__SANITIZE_ADDRESS__)
  // ASan's quarantine keeps freed blocks (256 MB by default), so RSS says
  // nothing here; this run still checks the path for memory errors and leaks.
  GTEST_SKIP() << "RSS bound not checked under AddressSanitizer (quarantine holds freed memory)";
#endif
  // Each pair holds 150 kB of pixels; a leak of one pair in ten would show as >130 MB.
  EXPECT_LT(rss_at_10000 - rss_at_1000, 8 * 1024) << "memory grew by " << (rss_at_10000 - rss_at_1000) << " kB";
}

}  // namespace
}  // namespace spinewatch
