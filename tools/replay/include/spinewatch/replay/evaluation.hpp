#pragma once
// Errors of an estimated posture stream against ground truth (the phantom's
// ground_truth.ndjson): neck, waist and every vertebra, per level and per
// axis, plus lost frames. Frames are matched by seq.
#include <array>
#include <string>
#include <vector>

#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

struct ErrorStats {
  std::size_t count = 0;
  double mean = 0, p95 = 0, max = 0;
};
ErrorStats summarise(std::vector<double> values);

// One trunk angle over the estimated frames: |published − true| in degrees;
// of the frames whose true angle is at least kTrunkBentDeg either way, how
// many the estimate bent the other way (any amount): the wrong side.
struct TrunkAngleScore {
  ErrorStats error;
  std::size_t bent_frames = 0, wrong_side = 0;
};
inline constexpr double kTrunkBentDeg = 5.0;

struct Evaluation {
  std::size_t truth_frames = 0;      // frames where the truth has a posture
  std::size_t estimated_frames = 0;  // of those, frames the estimate has a posture for
  std::size_t lost_frames = 0;       // truth has a posture, the estimate is lost or missing
  std::size_t init_frames = 0;       // estimate still initialising (not counted lost)
  std::vector<std::size_t> lost_seqs;
  ErrorStats neck, waist, all_vertebrae;
  std::array<ErrorStats, 3> neck_axis, waist_axis;         // |Δx|, |Δy|, |Δz|
  std::array<ErrorStats, kVertebraCount> per_level;        // 3D distance
  std::array<std::array<ErrorStats, 3>, kVertebraCount> per_level_axis;
  // Axial twist of T1 against L5 (swing-twist about the vertical), degrees:
  // |published − true|, over the estimated frames; and of the frames whose
  // true twist is 15° or more, how many were tracked as within 10° without
  // the twist_unresolved flag (a confident untwisted posture).
  ErrorStats twist;
  std::size_t twisted_frames = 0, twisted_published_untwisted = 0, twist_unresolved_frames = 0;
  // Trunk inclination and side bend (trunk_tilt), both postures measured in
  // the frame the truth faces, over the estimated frames with vertebrae.
  TrunkAngleScore inclination, side_bend;
};

// `include_init`: count provisional postures of the init state as estimates.
Evaluation evaluate(const std::vector<Posture>& estimate, const std::vector<Posture>& truth, bool include_init = false);
std::string format_evaluation(const Evaluation& e);

}  // namespace spinewatch
