#pragma once
// Offline replay of a recording directory through the estimator: frames in
// timestamp order → pairer (free-run, by timestamp) → PostureEstimator →
// one Posture per pair, as fast as the machine allows.
#include <cstdint>
#include <filesystem>
#include <functional>

#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/sync/pairing_stats.hpp"

namespace spinewatch {

// One processed pair with everything an observer (the overlay writer) may
// want to draw; references are valid only during the call.
struct ReplayedPair {
  const FramePair& pair;
  const Posture& posture;
  const EstimatorTrace& trace;
  const CameraRig& rig;
};
using PairObserver = std::function<Status(const ReplayedPair&)>;

struct ReplayOptions {
  EstimatorOptions estimator;
  // calibration.yaml to use instead of DIR/calibration.yaml.
  std::filesystem::path calibration;
  // The empty scene (docs/tuning.md, "Background"): the recording's own
  // DIR/background_{frontal,lateral}.png when present, else these (the
  // station's, from its configuration), else none: learnt or bootstrapped
  // (background = "learn"), or an error (background = "image").
  std::filesystem::path background_frontal, background_lateral;
  bool ignore_recording_background = false;  // the recording's own images are not used
  // Called after every pair, after its latency is measured; an error stops the replay.
  PairObserver observer;
};

struct ReplayStats {
  std::uint64_t pairs = 0;
  std::uint64_t lost = 0;  // postures with state lost
  sync::PairingStats pairing;
  bool default_rig = false;  // no calibration.yaml: the documented default rig was used
};

struct ReplayProgress {
  std::uint64_t pairs_done = 0;
  std::uint64_t pairs_expected = 0;  // min of the two streams' frame counts
};

using PostureConsumer = std::function<Status(const Posture&)>;
using ProgressSink = std::function<void(const ReplayProgress&)>;

// Errors: the recording's (file and problem) or the first error the sink returns.
Result<ReplayStats> replay_recording(const std::filesystem::path& dir, const ReplayOptions& options,
                                     const PostureConsumer& sink, const ProgressSink& progress = {});

}  // namespace spinewatch
