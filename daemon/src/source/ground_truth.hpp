#pragma once
// How far off the station is, live, on a recording that carries its ground
// truth (a phantom recording, docs/phantom.md: ground_truth.ndjson): every
// posture is scored against the truth of the recording pair it came from,
// and /state and the live view show the running figures
// (docs/daemon.md, "Live view and metrics").
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

#include "http/daemon_metrics.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

class GroundTruthScore {
 public:
  // DIR/ground_truth.ndjson when there is one; nothing when there is none;
  // an error naming the file and line when it does not read.
  static Result<std::optional<GroundTruthScore>> open(const std::filesystem::path& recording_dir);

  // `source_seq`: the pair's number in the recording source, which counts
  // on across loops (RecordingSource), so the truth is taken modulo the
  // recording's length. Only `tracking` postures are scored, as
  // `spinewatch eval` scores them; the others are counted.
  void score(std::uint64_t source_seq, const Posture& posture);
  TruthScoreStats stats() const;

  GroundTruthScore(GroundTruthScore&& other) noexcept;
  GroundTruthScore& operator=(GroundTruthScore&&) = delete;

 private:
  explicit GroundTruthScore(std::vector<std::optional<Posture>> truth) : truth_(std::move(truth)) {}

  std::vector<std::optional<Posture>> truth_;  // indexed by the recording's pair seq; empty where it has none
  mutable std::mutex mutex_;                   // score: the estimator thread; stats: the HTTP and control threads
  TruthScoreStats stats_;
};

}  // namespace spinewatch
