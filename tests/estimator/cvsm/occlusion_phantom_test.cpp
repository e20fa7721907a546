// A seated person behind a desk the stored background holds: the frontal
// silhouette ends at the desk's edge (docs/cvsm.md, "Occluded lower
// body"). Short renders of one subject through the CVSM; the truth is the
// phantom's.
#include <string>

#include <gtest/gtest.h>

#include "trust_run.hpp"

namespace spinewatch {
namespace {

test::TrustRun run_at_desk(const std::string& scenario, const std::string& subject_name, int frames) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  po.subject = test::load_named_subject(subject_name);
  po.frames = frames;
  po.seed = 3;
  po.desk = true;
  return test::track_for_trust(po, test::generic_subject_options(), scenario + " at the desk, " + subject_name);
}

// Without the occluder's edge the fit dragged the pelvis down to explain
// the hidden legs (the waist 180–210 mm off, docs/accuracy.md) or lost
// the person; with it the trunk's own outline decides, and a pair whose
// lower body neither view sees is lost, not published.
// (The tall subject is not asserted: it is still fitted standing behind
// the desk, docs/cvsm.md, "Occluded lower body".)
TEST(Occlusion, BehindADeskNoTrackedPostureIsConfidentlyWrong) {
  for (const char* scenario : {"seated_flexion", "typing"}) {
    const test::TrustRun run = run_at_desk(scenario, "petite", 30);
    EXPECT_EQ(run.wrong, 0) << scenario;
    EXPECT_LE(run.worst_mm, 45.0) << scenario;  // measured 36 and 9
  }
}

TEST(Occlusion, BehindADeskTheTrunkTracksWithTheWaistNearTheTruth) {
  const test::TrustRun run = run_at_desk("seated_flexion", "petite", 30);
  // Measured: all 21 pairs after the subject model's 9 init pairs tracked,
  // the waist 19.1 mm off on average (without the edge: never tracked).
  EXPECT_GE(run.tracking, 16);
  EXPECT_LE(run.waist_mean(), 25.0);
}

}  // namespace
}  // namespace spinewatch
