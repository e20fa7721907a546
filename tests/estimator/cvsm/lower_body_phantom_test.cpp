// The lower body in motion under the default (fixed) limbs (docs/cvsm.md,
// "A step aside"). A short render of one subject through the CVSM; the
// truth is the phantom's.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
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

// What the legs_unexplained check withheld on one render: the pairs it
// made lost, and how many of those the fit had more than 50 mm off.
struct Withheld {
  int pairs = 0, wrong = 0;
};
// One render of `scenario` for an ANSUR II subject: 60 person frames, seed 1.
phantom::PhantomOptions ansur_render(const std::string& scenario, const std::string& ansur_id) {
  phantom::PhantomOptions po;
  po.scenario = scenario;
  auto subject = phantom::load_ansur_subject("ansur:" + ansur_id,
                                             test::source_dir() + "/" + std::string(anthropometry::kAnsurRelativeDir));
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (subject.ok()) po.subject = *subject;
  po.frames = 60;
  po.seed = 1;
  return po;
}

test::TrustRun track_legs(const std::string& scenario, const std::string& ansur_id, Withheld& withheld) {
  const phantom::PhantomOptions po = ansur_render(scenario, ansur_id);
  auto each_fitted = [&](const phantom::PhantomFrame& f, const CvsmResult& r) {
    if (r.state != TrackingState::Lost || r.fit.flag != std::string(kLegsUnexplainedFlag)) return;
    ++withheld.pairs;
    double worst = 0;
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      worst = std::max(worst, (r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm());
    withheld.wrong += worst > test::kWrongMm;
  };
  const test::TrustRun run =
      test::track_for_trust(po, CvsmOptions{}, scenario + ", ansur " + ansur_id + ", default limbs", {}, each_fitted);
  std::printf("  legs_unexplained: %d pairs withheld, %d of them > %.0f mm off\n", withheld.pairs, withheld.wrong,
              test::kWrongMm);
  return run;
}

// A lunge and a stride under the default (auto) limbs, whose legs are held
// straight and closed (docs/cvsm.md, "Legs the fit leaves out"), on the
// subject the check was made on: where the fit leaned the trunk over legs
// the silhouettes show elsewhere, the pairs are lost, flagged
// legs_unexplained, and what stays tracking is right. Without the check
// (the withheld pairs tracked; the check does not change the tracker's fit) the lunge
// had 2 tracked postures more than 50 mm off; with it none, 13 tracked;
// the stride, all 51 tracked pairs right, loses none of them.
TEST(LowerBody, LegsTheFitLeavesOutAreNotTracked) {
  Withheld lunge_withheld, stride_withheld;
  const test::TrustRun lunge = track_legs("lunge", "28496", lunge_withheld);
  const test::TrustRun stride = track_legs("stride", "28496", stride_withheld);
  EXPECT_EQ(lunge.wrong, 0);
  EXPECT_EQ(stride.wrong, 0);
  // The check is what removed the lunge's: it withheld pairs the fit had
  // wrong, and none it had right.
  EXPECT_GE(lunge_withheld.wrong, 1);
  EXPECT_EQ(lunge_withheld.wrong, lunge_withheld.pairs);
  EXPECT_EQ(stride_withheld.pairs, 0);
  // Tracking is left where the fit is right.
  EXPECT_GE(lunge.tracking, 10);
  EXPECT_GE(stride.tracking, 50);
}

// The stride of subject 25762 (ANSUR II test set), where the step search
// did not explain the step: the pelvis tilted 7–16° under the trunk over a
// leg the model does not draw. The check withholds 3 pairs, each more than
// 50 mm off; 6 stay tracking wrong, leaning 7.1° (under the 8° bound) or
// not at all (docs/cvsm.md, "Legs the fit leaves out", "Left").
TEST(LowerBody, AStepReadAsALeanIsWithheldWhereTheLeanShows) {
  Withheld withheld;
  const test::TrustRun stride = track_legs("stride", "25762", withheld);
  EXPECT_GE(withheld.wrong, 3);
  EXPECT_EQ(withheld.wrong, withheld.pairs);
  EXPECT_LE(stride.wrong, 6);
  EXPECT_GE(stride.tracking, 45);
}

// After pairs a check withheld while the fit went on from their pose, the
// first pair to pass is held too, flagged reacquiring, and the next is
// tracked (docs/cvsm.md, "Reacquired after a withheld stretch"): lunges of
// two subjects of the ANSUR II test set whose legs the held-straight model
// cannot draw. Every held pair follows a withheld one and, where it fits
// with the margin a fit published again needs (below), is followed by a
// tracked or withheld pair, never by a second hold; and the held pairs are
// the fit walking back: further off, over both runs, than the pairs after
// them (here 64.4 and 52.6 mm held, 42.2 and 54.4 mm after; these lunges
// keep 2 and 6 tracked postures over 50 mm elsewhere, which this rule is
// not about: docs/cvsm.md).
// The margin below lost_cost a fit published again needs
// (CvsmTracker::Impl::kBuildingCostRise).
constexpr double kReacquiredCostMargin = 0.04;

TEST(LowerBody, TheFirstPairAfterAWithheldStretchIsHeldAndTheNextTracked) {
  int held = 0;
  double held_mm = 0, after_mm = 0;
  for (const char* ansur_id : {"11953", "25762"}) {
    const phantom::PhantomOptions po = ansur_render("lunge", ansur_id);
    struct Pair {
      TrackingState state;
      std::string flag;
      double worst_mm;
      double cost;
    };
    std::vector<Pair> pairs;
    auto each_fitted = [&](const phantom::PhantomFrame& f, const CvsmResult& r) {
      double worst = 0;
      for (std::size_t k = 0; k < kVertebraCount; ++k)
        worst = std::max(worst, (r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm());
      pairs.push_back({r.state, r.fit.flag.value_or(""), worst, r.fit.cost});
    };
    test::track_for_trust(po, CvsmOptions{}, std::string("lunge, ansur ") + ansur_id, {}, each_fitted);
    const int held_before = held;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].flag != kReacquiringFlag) continue;
      ++held;
      EXPECT_EQ(pairs[i].state, TrackingState::Lost);
      ASSERT_GT(i, 0u);
      EXPECT_EQ(pairs[i - 1].state, TrackingState::Lost) << ansur_id << " pair " << i;
      if (pairs[i - 1].flag == kReacquiringFlag) continue;  // held again: above the margin
      ASSERT_LT(i + 1, pairs.size());
      if (pairs[i].cost <= CvsmOptions{}.lost_cost - kReacquiredCostMargin) {
        EXPECT_NE(pairs[i + 1].flag, kReacquiringFlag) << ansur_id << " pair " << i;
      }
      held_mm += pairs[i].worst_mm;
      after_mm += pairs[i + 1].worst_mm;
      std::printf("  %s pair %zu held: %.1f mm; the next %s: %.1f mm\n", ansur_id, i, pairs[i].worst_mm,
                  pairs[i + 1].state == TrackingState::Tracking ? "tracked" : "withheld", pairs[i + 1].worst_mm);
    }
    EXPECT_GE(held - held_before, 1) << ansur_id;
  }
  EXPECT_GT(held_mm, after_mm);
}

// 17538 (1650 mm, 98 kg, a test-set adult) carrying a box: her fit hangs
// at the edge of lost (0.336–0.348 against lost_cost 0.35), 58–74 mm off,
// and every pair that dipped under lost_cost after a lost one was
// published: 23 postures more than 50 mm off in this render. After a pair
// not published, a fit is published again only with kBuildingCostRise to
// spare below lost_cost (confirm_after_withheld): none of hers is.
TEST(LowerBody, AFitAtTheEdgeOfLostAfterALostPairIsNotPublished) {
  int reacquiring = 0;
  const test::TrustRun run =
      test::track_for_trust(ansur_render("carry", "17538"), CvsmOptions{}, "carry, ansur 17538", {},
                            [&](const phantom::PhantomFrame&, const CvsmResult& r) {
                              reacquiring += r.fit.flag == std::string(kReacquiringFlag);
                            });
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GT(reacquiring, 10) << "held as reacquiring, not lost on its cost";
}

}  // namespace
}  // namespace spinewatch
