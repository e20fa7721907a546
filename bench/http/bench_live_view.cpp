// The live view's cost to the pipeline: the estimator thread's time per
// pair (PostureEstimator::process, then LiveView::offer, as in spinewatchd)
// with no viewer and with five MJPEG viewers connected to the real HTTP
// server over loopback, each draining /stream on its own thread. The
// pictures are drawn and encoded on the live view's thread (http.fps = 5);
// the estimator thread only copies a sample when one is due.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <optional>
#include <thread>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <benchmark/benchmark.h>
#include <boost/asio.hpp>
#include <spdlog/spdlog.h>

#include "../phantom_pairs.hpp"
#include <opencv2/imgcodecs.hpp>

#include "http/http_server.hpp"
#include "http/jpeg_encoder.hpp"
#include "http/live_view.hpp"
#include "spinewatch/overlay/overlay.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/phantom/phantom.hpp"

namespace spinewatch {
namespace {

constexpr std::int64_t kPeriodNs = 33'333'333;

// A viewer: GET /stream, then read and discard until told to stop.
void view(std::uint16_t port, const std::atomic<bool>& stop) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval tv{0, 100'000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
    const std::string request = "GET /stream HTTP/1.1\r\nHost: bench\r\n\r\n";
    ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    char buffer[65536];
    while (!stop) ::recv(fd, buffer, sizeof buffer, 0);
  }
  ::close(fd);
}

// The petite subject's flexion rendered, or the benchmark skipped with why.
struct FlexionRun {
  phantom::PhantomOptions options;
  std::vector<FramePair> pairs;
};
std::optional<FlexionRun> flexion_run(benchmark::State& state) {
  auto scene = bench::petite_flexion();
  if (!scene.ok()) {
    state.SkipWithError(scene.error().message.c_str());
    return std::nullopt;
  }
  FlexionRun run{*scene, bench::phantom_pairs(*scene)};
  if (run.pairs.size() <= static_cast<std::size_t>(run.options.empty_frames)) {
    state.SkipWithError("phantom frames");
    return std::nullopt;
  }
  return run;
}

void BM_PipelinePairWithViewers(benchmark::State& state) {
  const int viewers = static_cast<int>(state.range(0));
  spdlog::set_level(spdlog::level::warn);
  const auto run = flexion_run(state);
  if (!run) return;
  const phantom::PhantomOptions& options = run->options;
  const std::vector<FramePair>& pairs = run->pairs;
  EstimatorOptions estimator_options;
  estimator_options.subject.spine_placement = SpinePlacementMode::Generic;  // the petite subject is a generic one
  PostureEstimator estimator(options.rig, estimator_options);

  boost::asio::io_context io;
  auto work = boost::asio::make_work_guard(io);
  std::unique_ptr<HttpServer> server;
  LiveView live(options.rig, LiveViewOptions{.fps = 5.0}, [&server](std::shared_ptr<const LiveFrame> f) {
    if (server) server->on_frame(std::move(f));
  });
  auto started = HttpServer::start(io, HttpOptions{.endpoint = {"127.0.0.1", 0}}, HttpHandlers{}, StationInfo{}, live);
  if (!started.ok()) {
    state.SkipWithError(started.error().message.c_str());
    return;
  }
  server = std::move(started).value();
  std::thread io_thread([&io] { io.run(); });
  std::atomic<bool> stop{false};
  std::vector<std::thread> viewer_threads;
  for (int i = 0; i < viewers; ++i) viewer_threads.emplace_back(view, server->port(), std::cref(stop));
  while (server->stats().stream_viewers < static_cast<std::uint64_t>(viewers)) std::this_thread::sleep_for(std::chrono::milliseconds(5));

  std::uint64_t k = 0;
  auto one_pair = [&](std::size_t i) {
    FramePair pair = pairs[i];
    pair.sequence = k;
    pair.timestamp_ns = static_cast<std::int64_t>(k) * kPeriodNs;
    ++k;
    const Posture posture = estimator.process(pair);
    live.offer(pair, posture, estimator.last_trace());
    return posture;
  };
  const int first_tracked = options.empty_frames + EstimatorOptions{}.cvsm.subject_frames;
  for (int i = 0; i < first_tracked; ++i) one_pair(static_cast<std::size_t>(i));
  const int n = static_cast<int>(pairs.size()) - first_tracked;
  int phase_k = 0, lost = 0;
  const auto frames_before = live.stats().frames;
  for (auto _ : state) {
    const int phase = phase_k++ % (2 * n - 2);
    const Posture p = one_pair(static_cast<std::size_t>(first_tracked + (phase < n ? phase : 2 * n - 2 - phase)));
    lost += p.state == TrackingState::Lost;
    benchmark::DoNotOptimize(p.waist);
  }
  const auto frames = live.stats().frames - frames_before;
  state.counters["lost"] = lost;
  state.counters["viewers"] = static_cast<double>(server->stats().stream_viewers);
  state.counters["jpegs"] = static_cast<double>(frames);

  stop = true;
  for (auto& t : viewer_threads) t.join();
  server->stop();
  live.stop();
  work.reset();
  io.stop();
  io_thread.join();
}
BENCHMARK(BM_PipelinePairWithViewers)->Arg(0)->Arg(5)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

// One live-view picture to JPEG, as the live view's thread encodes it:
// the overlay of a phantom pair at the default scale (1 280 × 508, the
// camera's pixels under it), quality 80. Arg 0: JpegEncoder (TurboJPEG,
// one compressor kept); 1: the reference, cv::imencode (libjpeg's API
// through OpenCV, set up per picture), which the live view used before.
void BM_LiveViewJpeg(benchmark::State& state) {
  const auto run = flexion_run(state);
  if (!run) return;
  const phantom::PhantomOptions& options = run->options;
  const FramePair& pair = run->pairs[static_cast<std::size_t>(options.empty_frames)];
  OverlayScene overlay;
  overlay.rig = &options.rig;
  overlay.width = static_cast<int>(pair.frontal.format().width);
  overlay.height = static_cast<int>(pair.frontal.format().height);
  overlay.frames[0] = &pair.frontal;
  overlay.frames[1] = &pair.lateral;
  const cv::Mat picture = render_overlay(overlay, OverlayOptions{.scale = LiveViewOptions{}.scale});
  const int quality = LiveViewOptions{}.jpeg_quality;
  JpegEncoder encoder;
  std::size_t bytes = 0;
  for (auto _ : state) {
    if (state.range(0) == 0) {
      auto jpeg = encoder.encode(picture, quality);
      bytes = jpeg ? jpeg->size() : 0;
    } else {
      std::vector<std::uint8_t> jpeg;
      cv::imencode(".jpg", picture, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
      bytes = jpeg.size();
    }
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["bytes"] = static_cast<double>(bytes);
  state.counters["pixels"] = static_cast<double>(picture.total());
}
BENCHMARK(BM_LiveViewJpeg)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace spinewatch

BENCHMARK_MAIN();
