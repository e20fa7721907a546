#include "source/ground_truth.hpp"

#include <fstream>

#include <fmt/format.h>

#include "spinewatch/estimator/posture_json.hpp"

namespace spinewatch {
namespace {

double distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm(); }

}  // namespace

Result<std::optional<GroundTruthScore>> GroundTruthScore::open(const std::filesystem::path& recording_dir) {
  const auto path = recording_dir / "ground_truth.ndjson";
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::optional<GroundTruthScore>{};
  std::ifstream in(path);
  if (!in) return Error{fmt::format("{}: cannot be read", path.string())};
  auto lines = decode_posture_stream(in, path.string());
  if (!lines) return lines.error();
  std::vector<std::optional<Posture>> truth;
  for (NumberedPosture& line : *lines) {
    Posture& posture = line.posture;
    // A recording of a few minutes at most: a seq beyond a million is not a pair number.
    if (posture.seq > 1'000'000)
      return Error{fmt::format("{}:{}: seq {} is not a pair of a recording", path.string(), line.line, posture.seq)};
    if (truth.size() <= posture.seq) truth.resize(posture.seq + 1);
    if (posture.state != TrackingState::Lost && posture.vertebrae) truth[posture.seq] = std::move(posture);
  }
  return std::optional<GroundTruthScore>(GroundTruthScore(std::move(truth)));
}

GroundTruthScore::GroundTruthScore(GroundTruthScore&& other) noexcept
    : truth_(std::move(other.truth_)), stats_(other.stats_) {}

void GroundTruthScore::score(std::uint64_t source_seq, const Posture& posture) {
  if (truth_.empty()) return;
  const std::optional<Posture>& truth = truth_[source_seq % truth_.size()];
  if (!truth) return;  // the empty scene before the subject walks in
  std::lock_guard lock(mutex_);
  if (posture.state != TrackingState::Tracking || !posture.vertebrae) {
    ++stats_.pairs_not_tracking;
    return;
  }
  double sum = 0;
  for (std::size_t i = 0; i < kVertebraCount; ++i)
    sum += distance((*posture.vertebrae)[i].body_center, (*truth->vertebrae)[i].body_center);
  const double vertebrae = sum / static_cast<double>(kVertebraCount);
  const double neck = distance(posture.vertebrae->front().body_center, truth->vertebrae->front().body_center);
  const double waist = distance(posture.vertebrae->back().body_center, truth->vertebrae->back().body_center);
  const double n = static_cast<double>(++stats_.pairs);
  stats_.vertebrae_mean_mm += (vertebrae - stats_.vertebrae_mean_mm) / n;
  stats_.neck_mean_mm += (neck - stats_.neck_mean_mm) / n;
  stats_.waist_mean_mm += (waist - stats_.waist_mean_mm) / n;
  stats_.last_vertebrae_mm = vertebrae;
}

TruthScoreStats GroundTruthScore::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace spinewatch
