#include "spinewatch/replay/replay.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/recording_source.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch {
namespace {

Result<CameraRig> recording_rig(const std::filesystem::path& dir, const ReplayOptions& options, bool& default_rig) {
  default_rig = false;
  if (!options.calibration.empty()) return load_calibration(options.calibration);
  const auto path = dir / "calibration.yaml";
  if (std::filesystem::exists(path)) return load_calibration(path);
  default_rig = true;
  spdlog::info("{}: no calibration.yaml, using the default rig (docs/calibration.md)", dir.string());
  return CameraRig::default_rig();
}

// The stored backgrounds for background = "image", as 8-bit grey images.
Status load_backgrounds(const std::filesystem::path& dir, const ReplayOptions& options, PostureEstimator& estimator) {
  cv::Mat images[2];
  const std::filesystem::path paths[2] = {
      options.background_frontal.empty() ? dir / "background_frontal.png" : options.background_frontal,
      options.background_lateral.empty() ? dir / "background_lateral.png" : options.background_lateral};
  for (int v = 0; v < 2; ++v) {
    images[v] = cv::imread(paths[v].string(), cv::IMREAD_GRAYSCALE);
    if (images[v].empty()) return Error{fmt::format("{}: cannot be read as an image", paths[v].string())};
  }
  auto view = [](const cv::Mat& m) {
    return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0]), 1};
  };
  return estimator.set_backgrounds(view(images[0]), view(images[1]));
}

}  // namespace

Result<ReplayStats> replay_recording(const std::filesystem::path& dir, const ReplayOptions& options,
                                     const PostureSink& sink, const ProgressSink& progress) {
  auto source = RecordingSource::open(dir, RecordingSourceOptions{.paced = false, .loop = false});
  if (!source) return source.error();
  ReplayStats stats;
  auto rig = recording_rig(dir, options, stats.default_rig);
  if (!rig) return rig.error();

  const RecordingInfo& info = source->info();
  ReplayProgress state;
  state.pairs_expected = std::min(info.frames[0].size(), info.frames[1].size());

  sync::FramePairer pairer(sync::PairerOptions{.fps = info.fps});
  PostureEstimator estimator(*rig, options.estimator);
  if (options.estimator.background == "image")
    if (auto s = load_backgrounds(dir, options, estimator); !s) return s.error();

  auto drain = [&]() -> Status {
    while (auto pair = pairer.pop()) {
      // In replay, seq is the pair's sequence number in the recording (interfaces.md §3).
      pair->sequence = pair->frontal.sequence();
      const auto start = std::chrono::steady_clock::now();
      Posture posture = estimator.process(*pair);
      posture.latency_us = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count();
      ++stats.pairs;
      if (posture.state == TrackingState::Lost) ++stats.lost;
      if (auto s = sink(posture); !s) return s.error();
      if (options.observer) {
        const EstimatorTrace trace = estimator.last_trace();
        if (auto s = options.observer(ReplayedPair{*pair, posture, trace, *rig}); !s) return s.error();
      }
      ++state.pairs_done;
      if (progress) progress(state);
    }
    return Ok{};
  };

  while (auto frame = source->next()) {
    pairer.push(frame->view == View::Frontal ? sync::Stream::Frontal : sync::Stream::Lateral, std::move(frame->frame));
    if (auto s = drain(); !s) return s.error();
  }
  if (source->error()) return *source->error();
  pairer.flush();
  if (auto s = drain(); !s) return s.error();

  stats.pairing = pairer.stats();
  const auto unpaired = stats.pairing.drops[0].total_discarded() + stats.pairing.drops[1].total_discarded();
  if (unpaired > 0)
    spdlog::warn("{}: {} frames had no partner and were not paired ({})", dir.string(), unpaired,
                 stats.pairing.summary());
  return stats;
}

}  // namespace spinewatch
