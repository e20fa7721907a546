// The provisional subject model at the default provisional_frames (3) on
// measured adults (ANSUR II test set, docs/cvsm.md "Provisional model"):
// the early postures raise the share of person frames estimated to 90 %
// and more without one confidently wrong posture, and the checks of their
// own hold back the early pairs that were wrong on the varied phantom.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

phantom::PhantomOptions ansur_flexion(int id, int person_frames) {
  phantom::PhantomOptions po;
  po.scenario = "flexion";
  auto subject = phantom::load_ansur_subject("ansur:" + std::to_string(id),
                                             test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  if (subject.ok()) po.subject = *subject;
  po.frames = person_frames;
  return po;
}

// Issue 31's target: ≥ 90 % of person frames estimated. Before, nothing
// was tracking before the 10th pair (85 % of 60, 70 % of the 30 here).
TEST(ProvisionalModel, MeasuredAdultsBendingAreNinetyPercentTrackedWithNoWrongPosture) {
  for (const int id : {28496, 25762, 11953}) {
    const test::TrustRun run = test::track_for_trust(ansur_flexion(id, 30), CvsmOptions{}, "flexion " + std::to_string(id));
    ASSERT_EQ(run.person_frames, 30);
    EXPECT_GE(run.tracking, 27) << id;  // measured: 28, the first two pairs init
    EXPECT_EQ(run.wrong, 0) << id << ": worst " << run.worst_mm << " mm";
  }
}

// Turned 90° (side-on to the frontal camera) with the heading held facing
// it ([cvsm] heading = "fixed"), the model barely fits (cost 0.34,
// lost_cost 0.35) and is lost once complete; an early pair needs
// kBuildingCostRise to spare below lost_cost. Without it, pairs 6–8
// with the person were tracking 209 mm off. (With the default "front" the
// fit turns with him: 7 of 9 tracking, the worst vertebra 19 mm off.)
TEST(ProvisionalModel, NoEarlyPostureFromAFitAtTheEdgeOfLost) {
  phantom::PhantomOptions po = ansur_flexion(28496, 9);
  po.heading_deg = 90;
  CvsmOptions held;
  held.heading = HeadingRange::Fixed;
  const test::TrustRun run = test::track_for_trust(po, held, "flexion 28496, heading 90, held facing");
  EXPECT_EQ(run.tracking, 0) << "worst " << run.worst_mm << " mm";
}

// Carrying a box, 25762's allowed side leads its mirror by under 1 % of
// the silhouettes over the building's pairs (kHeadingMarginFraction): the
// views have not told the side he faces, and his model is 50 mm off from
// its first pair. Early pairs wait for the facing check's verdict; without
// that, pairs 2–4 with the person were tracking 50.6 mm off.
TEST(ProvisionalModel, NoEarlyPostureBeforeTheViewsTellTheSideFaced) {
  phantom::PhantomOptions po = ansur_flexion(25762, 9);
  po.scenario = "carry";
  const test::TrustRun run = test::track_for_trust(po, CvsmOptions{}, "carry 25762");
  EXPECT_EQ(run.tracking, 0) << "worst " << run.worst_mm << " mm";
}

// The subject steps out of both views for a moment while his model is
// built (three pairs see only the room): the model is then built from the
// pairs around the gap, and its early postures wait for it to be complete.
// Without that, 7 early postures are published here (26 mm off at worst);
// where the gaps were pairs the silhouette had wrong, they were 50–56 mm off.
TEST(ProvisionalModel, NoEarlyPostureOnceTheBuildingWasInterrupted) {
  phantom::PhantomOptions po = ansur_flexion(11953, 16);
  auto seq = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  const phantom::PhantomFrame empty = seq->render(0);
  const int first_person = po.empty_frames;
  int provisional = 0;
  const test::TrustRun run = test::track_for_trust(
      po, CvsmOptions{}, "flexion 11953, out of view on the building's 3rd-5th pairs",
      [&](const phantom::PhantomFrame&, const CvsmResult& r) { provisional += r.provisional; },
      {},
      [&](int index, phantom::PhantomFrame& f) {
        if (index >= first_person + 2 && index < first_person + 5) f.luma = empty.luma;
      });
  EXPECT_EQ(run.lost, 3);  // the pairs without him
  EXPECT_EQ(provisional, 0);
  EXPECT_GT(run.tracking, 0);
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
}

// The first 20 person pairs of the phantom's arms_overhead (60 person
// frames) for one subject, the raw tracker at its defaults.
struct ArmsRising {
  int tracking = 0;
  int moved = 0;        // withheld, moved_while_building
  int reacquiring = 0;  // held after it
  int wrong = 0;        // tracking more than kWrongMm off
  double worst_mm = 0;
};

ArmsRising track_arms_rising(int id) {
  constexpr int kHeldPairs = 20;
  phantom::PhantomOptions po = ansur_flexion(id, 60);
  po.scenario = "arms_overhead";
  ArmsRising a;
  int person = 0;
  test::track_for_trust(po, CvsmOptions{}, "arms overhead " + std::to_string(id), {},
                        [&](const phantom::PhantomFrame& f, const CvsmResult& r) {
                          if (person++ >= kHeldPairs) return;
                          if (r.state == TrackingState::Lost && r.fit.flag) {
                            a.moved += *r.fit.flag == kMovedWhileBuildingFlag;
                            a.reacquiring += *r.fit.flag == kReacquiringFlag;
                          }
                          if (r.state != TrackingState::Tracking) return;
                          ++a.tracking;
                          double worst = 0;
                          for (std::size_t k = 0; k < kVertebraCount; ++k)
                            worst = std::max(worst, (r.vertebrae[k].body_center -
                                                     (*f.truth.vertebrae)[k].body_center)
                                                        .norm());
                          a.worst_mm = std::max(a.worst_mm, worst);
                          a.wrong += worst > test::kWrongMm;
                        });
  return a;
}

// Arms going overhead while the model is built: the building's cost rises
// from 0.08 to 0.2 and more. The building's pairs after the first get the
// arms' pass (building_arms) and the shape is refined with the arms where
// it found them, so the raised arms are not taken into the height and
// breadths. Measured for 28496: 18 of the 20 tracking, the worst vertebra
// 21 mm off, none withheld; before, the shape took the arms in, the pair
// completing the model was withheld (moved_while_building) and the next
// held (reacquiring): 12 tracking, and 52 of his 60 person pairs against
// 58 now.
TEST(ProvisionalModel, ArmsRaisedWhileTheModelIsBuiltAreDrawnAndTracked) {
  const ArmsRising a = track_arms_rising(28496);
  EXPECT_EQ(a.moved + a.reacquiring, 0);
  EXPECT_GE(a.tracking, 17);
  EXPECT_EQ(a.wrong, 0) << "worst " << a.worst_mm << " mm";
}

// Where the building's arms' pass leaves more below the waist unexplained
// than a building pair may (kBuildingArmsLowerResidualMax: 11953's rising
// arms here), the arms are not drawn and the shape takes them in: the pair
// that completes the model is withheld and the next one that passes is
// held as reacquiring; the fit goes on from them. Measured here: those two
// were 107 and 60 mm off, the first tracking pair after them 43 mm.
// Unwithheld, the completing pair was tracking 91 mm (11953) and 60 mm
// (28496) off on the baseline's recordings (docs/cvsm.md, "Provisional
// model"). Later in the clip, as 11953's arms come down, one pair is still
// tracking 72 mm off (issue 31); this test holds the first 20 person pairs.
TEST(ProvisionalModel, ThePairCompletingAModelBuiltWhileTheArmsRoseIsWithheld) {
  const ArmsRising a = track_arms_rising(11953);
  EXPECT_EQ(a.moved, 1);
  EXPECT_EQ(a.reacquiring, 1);
  EXPECT_EQ(a.wrong, 0) << "worst " << a.worst_mm << " mm";
}


// A tall worker (ANSUR 28048, 1930 mm, a test-set adult) reaching forward
// while his model is built: his head is above both pictures, so no crown
// measures his stature and the model's height places his spine. Refined on
// every building pair, the height followed his reach (1930 → 1962 mm here)
// and the spine with it. Held where the building's fit rose beyond
// kBuildingCostRise (tracker_building.cpp). Measured here: neck 40.9 →
// 30.4 mm, waist 43.2 → 35.6 mm, 25 → 22 postures more than 50 mm off (on
// the baseline's recording, 30 → 22), all 53 pairs still tracking.
TEST(ProvisionalModel, AHeightNoCrownMeasuresIsNotTakenFromAReach) {
  phantom::PhantomOptions po = ansur_flexion(28048, 60);
  po.scenario = "reach";
  po.seed = 1;
  const test::TrustRun run = test::track_for_trust(po, CvsmOptions{}, "reach, ansur 28048");
  EXPECT_LE(run.neck_mean(), 34.0);
  EXPECT_LE(run.waist_mean(), 39.0);
  EXPECT_LE(run.wrong, 23) << "worst " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, 50);
}

}  // namespace
}  // namespace spinewatch
