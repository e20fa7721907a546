// The estimator on measured people it was not built from: a fixed subset
// of ANSUR II test subjects (both sexes, spread over stature), each
// rendered by the phantom with the spine placed from the subject's own
// skin landmarks, estimated pair by pair with the station's default
// (measured) spine placement; and the same people with the generic
// placement, which the measured one must beat. docs/anthropometry.md,
// "Population sweep", has the full table and the command.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/population/report.hpp"
#include "spinewatch/population/selection.hpp"
#include "spinewatch/population/sweep.hpp"
#include "test_support.hpp"

namespace spinewatch::population {
namespace {

const std::vector<anthropometry::AnsurSubject>& release() {
  static const auto subjects = [] {
    auto all = anthropometry::read_ansur(test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
    if (!all) throw std::runtime_error(all.error().message);
    return std::move(all).value();
  }();
  return subjects;
}

// Three men and three women of the test set, standing and seated.
std::vector<anthropometry::AnsurSubject> subset() {
  SelectionOptions o;
  o.men = 3;
  o.women = 3;
  return select_subjects(release(), o);
}

std::vector<Run> sweep(SpinePlacementMode placement) {
  SweepOptions o;
  o.scenarios = {"flexion", "seated_flexion"};
  o.estimator.subject.spine_placement = placement;
  std::vector<Run> runs;
  for (const auto& s : subset())
    for (const auto& scenario : o.scenarios) {
      auto r = run_subject(s, scenario, o);
      if (!r) throw std::runtime_error(r.error().message);
      runs.push_back(std::move(r).value());
    }
  return runs;
}

Pooled sweep_and_print(SpinePlacementMode placement, const char* title) {
  const auto runs = sweep(placement);
  std::cout << format_runs(runs) << format_pooled(pool(runs), title);
  return pool(runs);
}

TEST(PopulationSelection, BothSexesOfTheTestSetSpreadOverStature) {
  const auto s = subset();
  ASSERT_EQ(s.size(), 6U);
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(anthropometry::partition_of(s[i].id), anthropometry::Partition::Test) << s[i].id;
    EXPECT_EQ(s[i].sex, i < 3 ? anthropometry::Sex::Male : anthropometry::Sex::Female);
    EXPECT_GE(bmi(s[i]), 18.0);
    EXPECT_LE(bmi(s[i]), 38.0);
    if (i % 3 != 0) {
      EXPECT_GT(s[i].stature_mm, s[i - 1].stature_mm) << "rising stature within a sex";
    }
  }
  // The first and last thirds of each sex's stature range are represented.
  EXPECT_GT(s[2].stature_mm - s[0].stature_mm, 60);
  EXPECT_GT(s[5].stature_mm - s[3].stature_mm, 50);
}

// Measured on this subset (docs/anthropometry.md): these bounds are the
// present level with a margin, not the targets, which the sweep
// does not yet meet (the person-to-person spread of the iliac crest given
// the stature alone is 23 mm SD). The phantom draws each
// subject's skin-to-vertebra offsets and spine depth from the published
// rules' spread (the validation protocol, config/spine-depth.toml), so
// six subjects' vertical bias carries their drawn L5 offsets (±15 mm SD
// each, ±6 mm on a mean of six): the 40-subject sweep's is −1.8 mm.
// Measured: neck 12.5, waist 26.9, every vertebra 18.9 mm; vertical bias
// −2.5 (T1) … −18.1 (L5); anterior bias −0.8 … −4.9 mm per level (the
// 40-subject sweep: within 2.3 mm). With the rules at their means and a
// fixed phantom depth it measured 20.0, 24.3, 22.0; −11.9 … −13.1.
// The targets: 10, 10, 10 and 5.
constexpr double kNeckMean = 16, kWaistMean = 31, kVertebraeMean = 23, kVerticalBias = 21, kAnteriorBias = 7;

// One test, so that the measured sweep (the costly part: 12 runs through
// phantom and estimator, ~100 s under the sanitizers) runs once.
TEST(PopulationSweep, MeasuredPlacementOnTestSubjectsBeatsTheGenericSpine) {
  const Pooled p = sweep_and_print(SpinePlacementMode::Measured, "fixed subset, measured placement");
  EXPECT_EQ(p.lost, 0);
  EXPECT_GT(p.tracking, p.frames * 3 / 4);
  EXPECT_LE(p.stature_abs.max, 15.0) << "the stature from the top of the head";
  EXPECT_LE(p.neck.mean, kNeckMean);
  EXPECT_LE(p.waist.mean, kWaistMean);
  EXPECT_LE(p.vertebrae.mean, kVertebraeMean);
  for (std::size_t k = 0; k < kVertebraCount; ++k)
    EXPECT_LE(std::abs(p.bias[k].y()), kVerticalBias) << kVertebraNames[k] << ": the spine sits too high or too low";
  // The published depth rule in both: no systematic front–back offset
  // (with a fixed phantom depth and a template fraction it was +8…+13 mm).
  for (std::size_t k = 0; k < kVertebraCount; ++k)
    EXPECT_LE(std::abs(p.bias[k].x()), kAnteriorBias) << kVertebraNames[k] << ": the spine sits too far forward or back";

  const Pooled generic = sweep_and_print(SpinePlacementMode::Generic, "fixed subset, generic placement");
  // The generic spine sits 30–35 mm low in measured bodies.
  EXPECT_LT(generic.bias[kWaistIndex].y(), -15.0);
  EXPECT_LT(generic.bias[kNeckIndex].y(), -15.0);
  EXPECT_LT(p.vertebrae.mean, generic.vertebrae.mean - 5.0);
  EXPECT_LT(std::abs(p.bias[kWaistIndex].y()), std::abs(generic.bias[kWaistIndex].y()) - 10.0);
}

}  // namespace
}  // namespace spinewatch::population
