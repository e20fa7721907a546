// A seated person on a black office chair the stored background holds:
// from the front his dark trousers differ from the seat and backrest by
// less than the silhouette's threshold, and the silhouette's trunk ends
// at the shirt's hem (docs/cvsm.md, "A black chair"). The view's unseen
// pixels are left out of the cost, so the fit does not lift the pelvis
// to the hem. One of the varied phantom's rows (scripts/baseline-fit:
// seed 1, 60 person frames), the tallest test subject, through the
// tracker with its defaults.
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

// 11953 on the black chair in `scenario`, as the varied phantom renders him.
phantom::PhantomOptions on_the_black_chair(const char* scenario) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  auto subject = phantom::load_ansur_subject("ansur:11953", test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (subject.ok()) po.subject = *subject;
  po.frames = 60;
  po.seed = 1;
  po.chair = phantom::Chair::Black;
  return po;
}

TEST(Chair, DarkTrousersBeforeABlackChairDoNotLiftThePelvis) {
  const phantom::PhantomOptions po = on_the_black_chair("seated_flexion");
  const test::TrustRun run = test::track_for_trust(po, CvsmOptions{}, "seated_flexion on a black chair, 11953");
  // The fit's own vertebrae (the accurate model downstream smooths
  // them): without the unseen pixels 37 of 40 tracked pairs were more than
  // 50 mm off at some vertebra, the waist 54 mm on average; with them one
  // pair reaches 50.x mm, the waist 28 mm, tracked on 58 of 60.
  // (spinewatch replay of the same render: none over 28 mm.)
  EXPECT_LE(run.wrong, 1);
  EXPECT_LT(run.worst_mm, 55.0);
  EXPECT_GE(run.tracking, 54);
}

// The same man typing at a desk on the black chair: the desk hides his
// lower body from the front, and from the side his silhouette ends on
// the seat it cannot be told from, not on an edge. Neither view shows
// where his pelvis rests, as with a grey chair, whose seat's edge the
// occluder check finds (docs/cvsm.md, "A black chair", *Behind a desk*).
// Published, 58 of his 60 postures were 55–92 mm off at the waist (his
// seated stature estimated 190 mm short); they are withheld, flagged.
TEST(Chair, BehindADeskABlackSeatLeavesThePelvisUnseenFromTheSide) {
  const phantom::PhantomOptions po = on_the_black_chair("typing");
  int hidden_flagged = 0;
  const test::TrustRun run = test::track_for_trust(
      po, CvsmOptions{}, "typing on a black chair, 11953", {}, [&](const phantom::PhantomFrame&, const CvsmResult& r) {
        hidden_flagged += r.state == TrackingState::Lost && r.fit.flag == std::string(kLowerBodyHiddenFlag);
      });
  EXPECT_EQ(run.wrong, 0);
  EXPECT_GE(hidden_flagged, 40);
}

}  // namespace
}  // namespace spinewatch
