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
#include <time.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include "../phantom_pairs.hpp"
#include "mqtt/mqtt_publisher.hpp"
#include "publish/stream_lines.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"

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

// What both pipeline benchmarks share: phantom flexion pairs, the
// estimator past its subject model, and (mqtt_on) a publisher connected to
// a mosquitto of its own. `error` is set when something could not start.
class PipelineRig {
 public:
  explicit PipelineRig(bool mqtt_on) {
    spdlog::set_level(spdlog::level::warn);
    auto scene = bench::petite_flexion();
    if (!scene.ok()) {
      error = scene.error().message;
      return;
    }
    const phantom::PhantomOptions& options = *scene;
    pairs_ = bench::phantom_pairs(options);
    if (pairs_.empty()) {
      error = "phantom frames";
      return;
    }
    EstimatorOptions estimator_options;
    estimator_options.subject.spine_placement = SpinePlacementMode::Generic;
    estimator_.emplace(options.rig, estimator_options);
    if (mqtt_on && !start_mqtt()) return;
    first_tracked_ = options.empty_frames + EstimatorOptions{}.cvsm.subject_frames;
    for (int i = 0; i < first_tracked_; ++i) one_pair(static_cast<std::size_t>(i));
  }
  ~PipelineRig() {
    if (!mqtt_) return;
    mqtt_->stop();
    mqtt_.reset();
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(outbox_.string() + suffix);
  }

  // The estimator thread's work for the next pair of a back-and-forth walk
  // through the tracked part of the flexion: process, encode, offer.
  Posture next() {
    const int n = static_cast<int>(pairs_.size()) - first_tracked_;
    const int phase = phase_k_++ % (2 * n - 2);
    return one_pair(static_cast<std::size_t>(first_tracked_ + (phase < n ? phase : 2 * n - 2 - phase)));
  }

  void report(benchmark::State& state, int lost) {
    state.counters["lost"] = lost;
    if (!mqtt_) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const MqttStats s = mqtt_->stats();
    state.counters["published"] = static_cast<double>(s.published_posture);
    state.counters["dropped"] = static_cast<double>(s.dropped_disconnected + s.dropped_queue_full);
  }

  std::string error;

 private:
  bool start_mqtt() {
    const std::uint16_t port = free_port();
    broker_.emplace(port);
    outbox_ = std::filesystem::temp_directory_path() / ("bench_mqtt_outbox." + std::to_string(::getpid()) + ".db");
    MqttOptions o;
    o.url = {false, "127.0.0.1", port};
    o.station = "bench";
    o.posture_rate_hz = 120;  // every posture of the 30 Hz stream
    o.outbox_path = outbox_;
    auto started = MqttPublisher::start(o);
    if (!started.ok()) {
      error = started.error().message;
      return false;
    }
    mqtt_ = std::move(started).value();
    for (int i = 0; i < 200 && !mqtt_->stats().connected; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!mqtt_->stats().connected) error = "no connection to the local mosquitto";
    return error.empty();
  }

  Posture one_pair(std::size_t i) {
    FramePair pair = pairs_[i];
    pair.sequence = k_;
    pair.timestamp_ns = static_cast<std::int64_t>(k_) * kPeriodNs;
    ++k_;
    const Posture posture = estimator_->process(pair);
    const std::string line = encode_posture_line(posture, StreamStats{});
    if (mqtt_) mqtt_->offer_posture(posture.t_ns, line);
    benchmark::DoNotOptimize(line.data());
    return posture;
  }

  std::vector<FramePair> pairs_;
  std::optional<PostureEstimator> estimator_;
  std::optional<Broker> broker_;
  std::unique_ptr<MqttPublisher> mqtt_;
  std::filesystem::path outbox_;
  int first_tracked_ = 0;
  int phase_k_ = 0;
  std::uint64_t k_ = 0;
};

// Back to back: as fast as the estimator goes (about 1 400 postures a
// second, 47 times the station's rate), so the publisher's thread and
// mosquitto run flat out beside it. An upper bound on the interference.
void BM_PipelinePairWithMqtt(benchmark::State& state) {
  PipelineRig rig(state.range(0) != 0);
  if (!rig.error.empty()) {
    state.SkipWithError(rig.error.c_str());
    return;
  }
  int lost = 0;
  for (auto _ : state) {
    const Posture p = rig.next();
    lost += p.state == TrackingState::Lost;
    benchmark::DoNotOptimize(p.waist);
  }
  rig.report(state, lost);
}
BENCHMARK(BM_PipelinePairWithMqtt)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

// As the station runs: one pair every 33.3 ms (30 Hz), the publisher's
// thread and mosquitto waking for each posture in between. The time is
// the estimator thread's own CPU time per pair (CLOCK_THREAD_CPUTIME_ID),
// which is what MQTT could take from it: preemption by the other threads
// while it waits for the next pair is not its cost, and a pair processed
// late would show as more CPU only if caches or the core were taken from it.
void BM_PipelinePairPaced(benchmark::State& state) {
  PipelineRig rig(state.range(0) != 0);
  if (!rig.error.empty()) {
    state.SkipWithError(rig.error.c_str());
    return;
  }
  const auto thread_cpu_s = [] {
    timespec ts{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
  };
  int lost = 0;
  auto due = std::chrono::steady_clock::now();
  for (auto _ : state) {
    std::this_thread::sleep_until(due);
    due += std::chrono::nanoseconds(kPeriodNs);
    const double start = thread_cpu_s();
    const Posture p = rig.next();
    state.SetIterationTime(thread_cpu_s() - start);
    lost += p.state == TrackingState::Lost;
    benchmark::DoNotOptimize(p.waist);
  }
  rig.report(state, lost);
}
// 300 pairs: ten seconds of a station's stream for each run.
BENCHMARK(BM_PipelinePairPaced)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->UseManualTime()->Iterations(300);

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
