#pragma once
// The paper's remedy for its hand-tuned k and c: per-joint bending-stiffness
// scale factors fitted to ground-truth sequences.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"

namespace spinewatch {

struct FitOptions {
  int rounds = 3;                 // coordinate-descent sweeps over the joints
  double initial_log_step = 0.5;  // ln of the first trial factor
  std::size_t max_frames = 12;    // per sequence, evenly subsampled
};

struct FitResult {
  std::array<double, kJointCount> scale = DynamicsOptions::filled_ones();
  double initial_error_mm = 0, final_error_mm = 0;  // mean vertebra distance
  int evaluations = 0;
};

// Each truth frame with vertebrae gives the targets (neck, waist, end
// directions); the error is the mean body-centre distance after settle().
double deformation_error(const SpineModel& model, const DynamicsOptions& options,
                         const std::vector<std::vector<Posture>>& sequences, std::size_t max_frames);
FitResult fit_bending_scales(const SpineModel& model, const DynamicsOptions& options,
                             const std::vector<std::vector<Posture>>& sequences, const FitOptions& fit = {});

// `[spine.bending_scale]` TOML fragment, one key per joint.
std::string stiffness_fragment(const FitResult& result);
Result<std::array<double, kJointCount>> parse_stiffness_fragment(std::string_view toml_text, std::string_view source);

// Targets of a posture (neck, waist and their directions, from the end
// vertebrae when the dirs are absent).
std::optional<SpineTargets> targets_of(const Posture& posture);

}  // namespace spinewatch
