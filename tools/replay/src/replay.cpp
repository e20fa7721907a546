#include "spinewatch/replay/replay.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spinewatch/capture/background_images.hpp"
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
  // Not an error (the phantom's recordings are made on that rig), but the
  // estimate is only right for a recording that was.
  spdlog::warn("{}: no calibration.yaml: replaying on the default rig ({}; docs/calibration.md, \"The default rig\"); "
               "if the recording was made on another rig, put its calibration.yaml in the directory or give --calibration",
               dir.string(), CameraRig::kDefaultRigSummary);
  return CameraRig::default_rig();
}

// The stored background, in the order ReplayOptions documents; nothing
// when there is none (an error only when background = "image" needs one).
Result<std::optional<BackgroundImages>> stored_background(const std::filesystem::path& dir, const ReplayOptions& options,
                                                          const RecordingInfo& info) {
  const int w = static_cast<int>(info.format.width), h = static_cast<int>(info.format.height);
  if (!options.ignore_recording_background && has_background_images(dir)) {
    auto images = load_background_images(dir, w, h);
    if (!images) return images.error();
    spdlog::info("{}: background from the recording's {} and {}", dir.string(), kBackgroundFiles[0], kBackgroundFiles[1]);
    return std::optional<BackgroundImages>(std::move(images).value());
  }
  if (!options.background_frontal.empty() || !options.background_lateral.empty()) {
    auto images = load_background_images(options.background_frontal, options.background_lateral, w, h);
    if (!images) return images.error();
    return std::optional<BackgroundImages>(std::move(images).value());
  }
  if (options.estimator.silhouette.background == BackgroundMode::Image)
    return Error{fmt::format("{}: background = \"image\" but there is no background_frontal.png / background_lateral.png "
                             "and none is configured (spinewatch background --out DIR)",
                             dir.string())};
  return std::optional<BackgroundImages>{};
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
  if (!stats.default_rig)
    if (auto s = check_image_size(*rig, static_cast<int>(info.format.width), static_cast<int>(info.format.height)); !s)
      return Error{fmt::format("{}: {}",
                               options.calibration.empty() ? (dir / "calibration.yaml").string() : options.calibration.string(),
                               s.error().message)};
  ReplayProgress state;
  state.pairs_expected = std::min(info.frames[0].size(), info.frames[1].size());

  sync::FramePairer pairer(sync::PairerOptions{.fps = info.fps});
  EstimatorOptions estimator_options = options.estimator;
  estimator_options.fps = info.fps;
  PostureEstimator estimator(*rig, estimator_options);
  if (options.estimator.silhouette.background != BackgroundMode::Threshold) {
    auto background = stored_background(dir, options, info);
    if (!background) return background.error();
    if (*background)
      if (auto s = estimator.set_backgrounds((*background)->frontal.view(), (*background)->lateral.view()); !s)
        return s.error();
  }

  auto drain = [&]() -> Status {
    while (auto pair = pairer.pop()) {
      // In replay, seq is the pair's sequence number in the recording (docs/interfaces.md §3).
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
    pairer.push(frame->view, std::move(frame->frame));
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
