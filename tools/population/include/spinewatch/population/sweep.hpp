#pragma once
// The population sweep: each selected ANSUR II subject, rendered by the
// phantom (spine placed from the subject's own skin landmarks) in each
// scenario, through the whole per-pair estimator; errors of every tracking
// posture against the truth, per run and pooled (docs/anthropometry.md,
// "Population sweep").
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/frames/result.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "spinewatch/replay/evaluation.hpp"

namespace spinewatch::population {

struct SweepOptions {
  std::vector<std::string> scenarios = {"flexion", "lateral_left", "twist", "seated_flexion"};
  EstimatorOptions estimator;
  int frames = 0;         // person frames per run; 0 = the scenario's own
  int empty_frames = 10;  // the background is learnt from these
  // Each subject's own stature and mass given to the estimator, as for a
  // known worker (config [subject] or the set_worker command).
  bool known_worker = false;
  // Each subject's measured C7 and iliac-crest heights given too, as a
  // station's set-up measures them with a tape (KnownWorker).
  bool known_landmarks = false;
  // How the phantom takes the published placement and depth rules for each
  // subject: drawn from their spread (the validation protocol), or at the
  // means the estimator assumes (self-consistency only).
  phantom::RuleDraw rules = phantom::RuleDraw::Drawn;
  std::uint32_t seed = 1;
};

// One subject in one scenario.
struct Run {
  int subject_id = 0;
  anthropometry::Sex sex = anthropometry::Sex::Male;
  double stature_mm = 0, bmi = 0;
  std::string scenario;
  // The subject model's stature: the one its spine was placed for, else
  // its height (0: never built).
  double model_height_mm = 0;
  int frames = 0;              // pairs with the subject in view
  int tracking = 0, init = 0, lost = 0;
  // Per tracking pair: |Δ| of T1 and L5, and every vertebra's signed Δ
  // (estimate − truth; x anterior, y up, z right).
  std::vector<double> neck, waist;
  std::array<std::vector<Eigen::Vector3d>, kVertebraCount> delta;
};

Result<Run> run_subject(const anthropometry::AnsurSubject& subject, const std::string& scenario,
                        const SweepOptions& options);

// Errors pooled over runs (every tracking pair of every run counts once).
struct Pooled {
  int runs = 0, frames = 0, tracking = 0, init = 0, lost = 0;
  ErrorStats neck, waist, vertebrae;
  std::array<ErrorStats, kVertebraCount> per_level;
  std::array<Eigen::Vector3d, kVertebraCount> bias{};  // mean signed Δ per level
  ErrorStats stature_abs;  // |model height − stature|, standing runs
  double stature_bias = 0;  // mean signed, standing runs
  double worst_level_mean = 0;  // the largest per-level mean
  double worst_bias = 0;        // the largest |component| of any level's bias
};
Pooled pool(const std::vector<Run>& runs);

}  // namespace spinewatch::population
