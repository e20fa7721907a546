// MQTT's cost to the pipeline (docs/performance.md, "MQTT"): the estimator
// thread's time per pair — PostureEstimator::process, the posture line
// encoded, then (Arg 1) MqttPublisher::offer_posture as spinewatchd does —
// without MQTT and with every posture published (posture_rate_hz = 120,
// above the 30 Hz pair rate; QoS 0) to a real mosquitto on loopback that
// this benchmark starts on a free port. The publishing itself runs on the
// publisher's thread; the estimator thread only copies a due line into a
// bounded queue.
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include "spinewatch/daemon/mqtt_publisher.hpp"
#include "spinewatch/daemon/stream_lines.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "../phantom_pairs.hpp"

extern char** environ;

namespace spinewatch {
namespace {

constexpr std::int64_t kPeriodNs = 33'333'333;

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

// mosquitto on loopback for the benchmark's life.
class Broker {
 public:
  explicit Broker(std::uint16_t port) : dir_(std::filesystem::temp_directory_path() / ("bench_mqtt." + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    const auto conf = dir_ / "mosquitto.conf";
    std::ofstream(conf) << "listener " << port << " 127.0.0.1\nallow_anonymous true\nlog_type none\n"
                        << (::geteuid() == 0 ? "user root\n" : "");
    const std::string c = conf.string();
    std::vector<char*> argv{const_cast<char*>("/usr/sbin/mosquitto"), const_cast<char*>("-c"), const_cast<char*>(c.c_str()), nullptr};
    if (posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ) != 0) pid_ = -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  ~Broker() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
    std::filesystem::remove_all(dir_);
  }
  bool running() const { return pid_ > 0; }

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

void BM_PipelinePairWithMqtt(benchmark::State& state) {
  const bool mqtt_on = state.range(0) != 0;
  spdlog::set_level(spdlog::level::warn);
  phantom::PhantomOptions options;
  options.scenario = "flexion";
  options.frames = 90;
  auto subject = phantom::load_subject(std::string(SPINEWATCH_SOURCE_DIR) + "/config/subjects/petite.json");
  if (!subject.ok()) {
    state.SkipWithError(subject.error().message.c_str());
    return;
  }
  options.subject = *subject;
  const auto pairs = bench::phantom_pairs(options);
  if (pairs.empty()) {
    state.SkipWithError("phantom frames");
    return;
  }
  EstimatorOptions estimator_options;
  estimator_options.spine_placement = SpinePlacementMode::Generic;
  PostureEstimator estimator(options.rig, estimator_options);

  const std::uint16_t port = free_port();
  std::optional<Broker> broker;
  std::unique_ptr<MqttPublisher> mqtt;
  const auto outbox = std::filesystem::temp_directory_path() / ("bench_mqtt_outbox." + std::to_string(::getpid()) + ".db");
  if (mqtt_on) {
    broker.emplace(port);
    MqttOptions o;
    o.url = {false, "127.0.0.1", port};
    o.station = "bench";
    o.posture_rate_hz = 120;  // every posture of the 30 Hz stream
    o.outbox_path = outbox;
    auto started = MqttPublisher::start(o);
    if (!started.ok()) {
      state.SkipWithError(started.error().message.c_str());
      return;
    }
    mqtt = std::move(started).value();
    for (int i = 0; i < 200 && !mqtt->stats().connected; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!mqtt->stats().connected) {
      state.SkipWithError("no connection to the local mosquitto");
      return;
    }
  }

  std::uint64_t k = 0;
  auto one_pair = [&](std::size_t i) {
    FramePair pair = pairs[i];
    pair.sequence = k;
    pair.timestamp_ns = static_cast<std::int64_t>(k) * kPeriodNs;
    ++k;
    const Posture posture = estimator.process(pair);
    const std::string line = encode_posture_line(posture, StreamStats{});
    if (mqtt) mqtt->offer_posture(posture.t_ns, line);
    benchmark::DoNotOptimize(line.data());
    return posture;
  };
  const int first_tracked = options.empty_frames + EstimatorOptions{}.subject_frames;
  for (int i = 0; i < first_tracked; ++i) one_pair(static_cast<std::size_t>(i));
  const int n = static_cast<int>(pairs.size()) - first_tracked;
  int phase_k = 0, lost = 0;
  for (auto _ : state) {
    const int phase = phase_k++ % (2 * n - 2);
    const Posture p = one_pair(static_cast<std::size_t>(first_tracked + (phase < n ? phase : 2 * n - 2 - phase)));
    lost += p.state == TrackingState::Lost;
    benchmark::DoNotOptimize(p.waist);
  }
  state.counters["lost"] = lost;
  if (mqtt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const MqttStats s = mqtt->stats();
    state.counters["published"] = static_cast<double>(s.published_posture);
    state.counters["dropped"] = static_cast<double>(s.dropped_disconnected + s.dropped_queue_full);
    mqtt->stop();
    mqtt.reset();
    std::filesystem::remove(outbox);
    std::filesystem::remove(outbox.string() + "-wal");
    std::filesystem::remove(outbox.string() + "-shm");
  }
}
BENCHMARK(BM_PipelinePairWithMqtt)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

// The hand-over alone, as the estimator thread pays it per posture: a
// 3 kB posture line offered to a connected publisher, every one due.
void BM_OfferPosture(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  const std::uint16_t port = free_port();
  Broker broker(port);
  const auto outbox = std::filesystem::temp_directory_path() / ("bench_mqtt_offer." + std::to_string(::getpid()) + ".db");
  MqttOptions o;
  o.url = {false, "127.0.0.1", port};
  o.station = "bench";
  o.posture_rate_hz = 120;
  o.outbox_path = outbox;
  auto mqtt = MqttPublisher::start(o);
  if (!mqtt.ok()) {
    state.SkipWithError(mqtt.error().message.c_str());
    return;
  }
  for (int i = 0; i < 200 && !(*mqtt)->stats().connected; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::string line(3000, 'x');
  std::int64_t t = 0;
  for (auto _ : state) {
    (*mqtt)->offer_posture(t, line);
    t += kPeriodNs;
  }
  const MqttStats s = (*mqtt)->stats();
  state.counters["dropped_queue_full"] = static_cast<double>(s.dropped_queue_full);
  (*mqtt)->stop();
  std::filesystem::remove(outbox);
  std::filesystem::remove(outbox.string() + "-wal");
  std::filesystem::remove(outbox.string() + "-shm");
}
BENCHMARK(BM_OfferPosture)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace spinewatch

BENCHMARK_MAIN();
