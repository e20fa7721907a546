// The lower body in motion under the default (fixed) limbs (docs/cvsm.md,
// "A step aside"). A short render of one subject through the CVSM; the
// truth is the phantom's.
#include <gtest/gtest.h>

#include "trust_run.hpp"

namespace spinewatch {
namespace {

// `stride` in 36 person frames: steps in place, then a step 250 mm aside.
// The template's straight, closed legs and the translation's anchor held
// the pelvis over the leg that stood still while the body stepped, and the
// trunk bent over to reach the shoulders: before the step search, 5 of 25
// tracked postures were more than 50 mm off (worst 91 mm; neck 18.4 mm,
// waist 24.0 mm on average). With it: 27 tracked, none wrong (worst 22 mm;
// neck 8.1, waist 12.9 mm).
TEST(LowerBody, AStepAsideIsFollowedNotBentInto) {
  phantom::PhantomOptions po;
  po.scenario = "stride";
  po.subject = test::load_named_subject("ansur-15936");
  po.frames = 36;
  po.seed = 3;
  const test::TrustRun run = test::track_for_trust(po, CvsmOptions{}, "stride, ansur-15936, default limbs");
  EXPECT_EQ(run.wrong, 0);
  EXPECT_LE(run.worst_mm, 48.0);
  EXPECT_GE(run.tracking, 25);
  EXPECT_LE(run.waist_mean(), 18.0);
}

}  // namespace
}  // namespace spinewatch
