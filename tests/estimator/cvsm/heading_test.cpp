// The subject facing any direction (docs/cvsm.md, "Heading"): short
// phantom renders of a measured adult turned away from the frontal camera,
// tracked by the CVSM from their images alone. What is published as
// tracking is right (no vertebra more than 50 mm from the truth, the issue's
// "confidently wrong" line) and the heading found is the rendered one.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "test_support.hpp"
#include "trust_run.hpp"

namespace spinewatch {
namespace {

struct HeadingRun : test::TrustRun {
  double worst_heading_deg = 0;        // the farthest tracked heading from the rendered one
  double farthest_from_front_deg = 0;  // the farthest tracked heading from facing the frontal camera
  int facing_away = 0;                 // pairs lost with the flag facing_away
};

double apart_deg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return d > 180 ? 360 - d : d;
}

// A measured adult of the ANSUR II release ("ansur:ID").
phantom::Subject ansur_subject(const char* id) {
  auto subject = phantom::load_ansur_subject(id, test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
  EXPECT_TRUE(subject.ok()) << subject.error().message;
  return subject.ok() ? *subject : phantom::Subject{};
}

// The render's scenario and subject: flexion, and the measured adult the
// project keeps in config/subjects/, unless given.
struct Render {
  const char* scenario = "flexion";
  std::optional<phantom::Subject> subject;
};

HeadingRun run_turned(double heading_deg, LimbMode limbs, HeadingRange range, const Render& render = {}) {
  phantom::PhantomOptions po;
  po.scenario = render.scenario;
  po.subject = render.subject ? *render.subject : test::load_named_subject("ansur-15936");
  po.frames = 24;  // 10 build the subject model, 14 bend forward
  po.seed = 2;
  po.heading_deg = heading_deg;
  CvsmOptions options;
  options.limbs = limbs;
  options.heading = range;
  HeadingRun run;
  static_cast<test::TrustRun&>(run) =
      test::track_for_trust(po, options, "heading " + std::to_string(heading_deg), [&](const phantom::PhantomFrame&, const CvsmResult& r) {
        run.worst_heading_deg = std::max(run.worst_heading_deg, apart_deg(r.pose.heading, heading_deg));
        run.farthest_from_front_deg = std::max(run.farthest_from_front_deg, apart_deg(r.pose.heading, 0));
      }, [&](const phantom::PhantomFrame&, const CvsmResult& r) {
        run.facing_away += r.state == TrackingState::Lost && r.fit.flag == std::string(kFacingAwayFlag);
      });
  return run;
}

// Trackable, so tracked (by default every pair after the subject model),
// none wrong, at the rendered heading.
void expect_right_or_silent(double heading_deg, LimbMode limbs, HeadingRange range, const Render& render = {},
                            int min_tracking = 14) {
  const HeadingRun run = run_turned(heading_deg, limbs, range, render);
  const std::string what = std::string(render.scenario) + ", heading " + std::to_string(heading_deg) +
                           (limbs == LimbMode::Fixed ? ", fixed" : ", articulated");
  ASSERT_EQ(run.person_frames, 24) << what;
  EXPECT_EQ(run.wrong, 0) << what << ": worst tracking vertebra " << run.worst_mm << " mm";
  EXPECT_GE(run.tracking, min_tracking) << what;
  EXPECT_LE(run.worst_heading_deg, 10) << what;
}

TEST(CvsmHeading, BackToTheFrontalCameraTrackedRight) { expect_right_or_silent(180, LimbMode::Fixed, HeadingRange::Any); }
// 90° is the edge of the front half: found with either range.
TEST(CvsmHeading, FacingAwayFromTheLateralCameraTrackedRight) {
  expect_right_or_silent(90, LimbMode::Fixed, HeadingRange::Front);
  expect_right_or_silent(90, LimbMode::Fixed, HeadingRange::Any);
}
TEST(CvsmHeading, BackToTheFrontalCameraArticulatedTrackedRight) {
  expect_right_or_silent(180, LimbMode::Articulated, HeadingRange::Any);
}

// A box carried at the belly, facing the frontal camera: the model (arms
// hanging, no box) explains a third of the silhouettes' pixels badly
// whichever way it faces, and a probe's short shape fit from the first
// pair's measurements had turned him round by its convergence (docs/cvsm.md,
// "Heading"). Over the full circle the fit never faces away, on any pair
// with a person (the pose the tracker holds, published or not), and
// nothing is confidently wrong.
TEST(CvsmHeading, ABoxCarriedDoesNotTurnTheSubjectRound) {
  phantom::PhantomOptions po;
  po.scenario = "carry";
  po.subject = test::load_named_subject("ansur-15936");
  po.frames = 24;
  po.seed = 2;
  auto seq = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmOptions options;
  options.heading = HeadingRange::Any;
  CvsmTracker tracker(seq->options().rig, options);
  int person_frames = 0, init = 0, wrong = 0;
  double farthest = 0;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    const CvsmResult r = tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
    if (!f.truth.vertebrae) continue;
    ++person_frames;
    init += r.state == TrackingState::Init;
    farthest = std::max(farthest, apart_deg(r.pose.heading, 0));
    if (r.state != TrackingState::Tracking) continue;
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      if ((r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm() > test::kWrongMm) {
        ++wrong;
        break;
      }
  }
  std::printf("carry, full circle: %d person frames, %d init, farthest heading from facing %.1f deg, %d wrong\n",
              person_frames, init, farthest, wrong);
  ASSERT_EQ(person_frames, 24);
  ASSERT_GT(init, 0);  // the subject model was built
  EXPECT_LE(farthest, 10.0);
  EXPECT_EQ(wrong, 0);
}

// [cvsm] heading = "fixed": the subject is held facing the frontal camera,
// the fit as it was without a heading.
TEST(CvsmHeading, TheFixedRangeHoldsTheSubjectFacingTheFrontalCamera) {
  const HeadingRun run = run_turned(30, LimbMode::Fixed, HeadingRange::Fixed);
  ASSERT_EQ(run.person_frames, 24);
  ASSERT_GT(run.tracking, 0);
  EXPECT_EQ(run.farthest_from_front_deg, 0.0);
}

// A seated worker behind a desk, facing the frontal camera: the desk cuts
// his frontal outline and a turned model explains the rest a few per cent
// better, never by the front range's preference for facing the camera;
// the settling steps and the per-pair steps must not walk him round by
// gains each below it (docs/cvsm.md, "Heading").
TEST(CvsmHeading, TheFrontRangeKeepsASeatedWorkerBehindADeskFacingTheCamera) {
  phantom::PhantomOptions po;
  po.scenario = "typing";
  po.subject = test::load_named_subject("ansur-15936");
  po.frames = 24;
  po.seed = 2;
  po.desk = true;
  CvsmOptions options;
  options.heading = HeadingRange::Front;
  // The desk hides his lower body in both views: the pairs are lost
  // (lower_body_hidden) but fitted, and the fit goes on from each: its
  // heading is judged on all of them.
  double farthest = 0;
  int fitted = 0;
  const test::TrustRun run = test::track_for_trust(po, options, "typing at the desk, front range", {},
                                                   [&](const phantom::PhantomFrame&, const CvsmResult& r) {
                                                     ++fitted;
                                                     farthest = std::max(farthest, apart_deg(r.pose.heading, 0));
                                                   });
  ASSERT_GT(fitted, 12);
  EXPECT_EQ(farthest, 0.0);
  EXPECT_EQ(run.wrong, 0);
}

// A tall, heavy man (ANSUR 11953) bending forward seated behind a desk, his
// stature given: on the first pair his sides are weighed against each other,
// and with only the desk's straight run hidden his thighs, turned 30° with
// the model, were charged beside it where the desk hides them; his mirror
// led by 3 % of the silhouettes, the front range followed him "turned
// away", and his pairs were published as his mirror image, 118–160 mm off. The
// sides are weighed with every column the desk's edge cuts him on hidden
// (docs/cvsm.md, "Turned away from the range").
TEST(CvsmHeading, ASeatedManBehindADeskIsNotWeighedIntoHisMirror) {
  phantom::PhantomOptions po;
  po.scenario = "seated_flexion";
  po.subject = ansur_subject("ansur:11953");
  po.frames = 60;
  po.desk = true;
  CvsmOptions options;
  options.stature_mm = 1838;  // his, from ANSUR II
  double farthest = 0;
  const test::TrustRun run = test::track_for_trust(po, options, "seated flexion at the desk, 11953, stature given", {},
                                                   [&](const phantom::PhantomFrame&, const CvsmResult& r) {
                                                     farthest = std::max(farthest, apart_deg(r.pose.heading, 0));
                                                   });
  ASSERT_EQ(run.person_frames, 60);
  // Measured: 24 pairs tracking (the rest lost, lower_body_hidden), neck
  // 28.5 mm, worst vertebra 32 mm; before, 24 tracking, every one of them
  // more than 50 mm off (the worst 160 mm), facing away.
  EXPECT_LE(farthest, 30.0);
  EXPECT_EQ(run.wrong, 0) << "worst " << run.worst_mm << " mm";
  EXPECT_GT(run.tracking, 0);
}

// A seated adult facing the frontal camera, with the front range: the
// heading is first chosen on the standing model every first pair starts
// from, and as a standing man ANSUR 27006 seated drew better turned 30°;
// his shape was built turned and, over the population run, every vertebra
// came out 41 mm off on average where the fixed range had 22 (docs/cvsm.md,
// "Heading"). With the heading chosen again once he is seen seated, the
// front range fits him facing the camera, as well as the fixed range does.
// (This short render is hard for both: its waist about 50 mm off.)
TEST(CvsmHeading, TheFrontRangeFitsASeatedAdultFacingTheCameraFacingIt) {
  phantom::PhantomOptions po;
  po.scenario = "seated_flexion";
  po.subject = ansur_subject("ansur:27006");
  po.frames = 20;
  CvsmOptions front, fixed;
  front.heading = HeadingRange::Front;
  fixed.heading = HeadingRange::Fixed;
  double farthest = 0;
  const test::TrustRun run = test::track_for_trust(po, front, "seated flexion 27006, front range",
                                                   [&](const phantom::PhantomFrame&, const CvsmResult& r) {
                                                     farthest = std::max(farthest, apart_deg(r.pose.heading, 0));
                                                   });
  const test::TrustRun held = test::track_for_trust(po, fixed, "seated flexion 27006, fixed range");
  ASSERT_EQ(run.person_frames, 20);
  // Measured: 0° (before, 30° from the first pair on).
  EXPECT_LE(farthest, 10.0);
  // Measured: front 14 tracking, neck / waist 20.4 / 48.2 mm, 5 pairs over
  // 50 mm; fixed 18, 16.8 / 30.5 mm, none. Before the silhouette's unseen
  // pixels (docs/cvsm.md, "A black chair") the two were alike: front 14,
  // 20.1 / 54.0 mm, 10 over 50 mm; fixed 16, 20.7 / 48.6 mm, 6. The fixed
  // range gained more from them, so the front range is held to its own
  // figures and to the fixed range's tracking.
  EXPECT_GE(run.tracking, held.tracking - 4);
  EXPECT_LE(run.neck_mean(), held.neck_mean() + 6);
  EXPECT_LE(run.waist_mean(), 54.0);
  EXPECT_LE(run.wrong, 5);
}

// A range that does not take the side turned away ("fixed") and a subject
// with his back to the frontal camera: fitted facing it he would be his own
// mirror image, every posture confidently wrong (a forward bend read as an
// extension). The views tell the sides apart, and every pair after the
// subject model is lost, flagged facing_away (docs/cvsm.md, "Turned away
// from the range").
void expect_lost_facing_away(double heading_deg, HeadingRange range, const Render& render = {}) {
  const HeadingRun run = run_turned(heading_deg, LimbMode::Fixed, range, render);
  const std::string what = std::string(render.scenario) + ", heading " + std::to_string(heading_deg);
  ASSERT_EQ(run.person_frames, 24) << what;
  EXPECT_EQ(run.tracking, 0) << what;
  EXPECT_EQ(run.wrong, 0) << what << ": worst tracking vertebra " << run.worst_mm << " mm";
  EXPECT_GE(run.facing_away, 14) << what;
}
TEST(CvsmHeading, TheFixedRangeSaysLostWithTheBackToTheFrontalCamera) {
  expect_lost_facing_away(180, HeadingRange::Fixed);
  // 30° off the back, where the views lead for the mirror by less on each
  // pair: decided on the pair that completes the subject model.
  expect_lost_facing_away(210, HeadingRange::Fixed);
}
// The front range (the default) decides the same way that he has his back
// to the frontal camera, and where the views decide it by the margin the
// side turned away needs (kAwayPreferenceFraction, summed over the
// building pairs), follows and publishes him turned away (docs/cvsm.md,
// "Turned away from the range"). Before, every pair was lost, facing_away.
TEST(CvsmHeading, TheFrontRangeTracksTheSubjectWithHisBackToTheFrontalCamera) {
  expect_right_or_silent(180, LimbMode::Fixed, HeadingRange::Front);
}
// Seated with his back to the frontal camera: the seated model facing the
// camera has its thighs where his back is and loses, the standing one wins,
// and standing against its mirror the straight legs do not tell the side.
// Before the posture was chosen at the reflection too
// (seat_if_turned_away, facing_check.hpp), two of the varied phantom's
// test subjects were tracked as short standing men leaning back, every
// posture 160–210 mm off (docs/cvsm.md, "Turned away from the range"); in
// these 24-frame renders 11953 was tracked 13 times up to 243 mm off with
// either range, 28496 was lost as it should be.
TEST(CvsmHeading, TheFrontRangeTracksASeatedSubjectWithHisBackToTheFrontalCamera) {
  expect_right_or_silent(180, LimbMode::Fixed, HeadingRange::Front, {"seated_flexion", ansur_subject("ansur:28496")});
  expect_right_or_silent(180, LimbMode::Fixed, HeadingRange::Front, {"seated_flexion", ansur_subject("ansur:11953")});
}
TEST(CvsmHeading, TheFixedRangeSaysLostSeatedWithTheBackToTheFrontalCamera) {
  expect_lost_facing_away(180, HeadingRange::Fixed, {"seated_flexion", ansur_subject("ansur:11953")});
}
// Turned 120° or 150°, his back three-quarters to the frontal camera: the
// frontal view is the one of a man turned 60° or 30° towards it (a heading
// h and 180° − h draw the same frontal outline), and the front range fits
// him there; only the lateral view tells them apart. The check weighs the
// side allowed against that reflection (and 30° either side of each), not
// against the allowed side turned 180°, which neither view confuses with
// it: before, the varied phantom's three subjects turned 120° and 150° were
// tracked 209 times more than 50 mm off (docs/cvsm.md, "Turned away from
// the range"). Decided turned away, he is tracked there: every pair after
// the subject model, within 10° of the rendered heading. (Before the
// building's heading search was turned to the side he faces, 120° was
// tracked at its reflection, 60°, up to 49 mm off.)
TEST(CvsmHeading, TheFrontRangeTracksTheSubjectTurnedThreeQuartersAway) {
  expect_right_or_silent(120, LimbMode::Fixed, HeadingRange::Front);
  expect_right_or_silent(150, LimbMode::Fixed, HeadingRange::Front);
}
// He leaves and comes back with his back to the frontal camera: the range
// still does not take that side, and the pair that finds him again weighs
// it (docs/cvsm.md, "Turned away from the range"). The first render
// (facing) is tracked; the second (turned 180°, after its empty frames)
// has nothing tracking more than 50 mm off and is lost, facing_away.
TEST(CvsmHeading, TheFixedRangeSaysLostWhenHeComesBackTurnedAway) {
  auto render = [](double heading_deg) {
    phantom::PhantomOptions po;
    po.scenario = "flexion";
    po.subject = test::load_named_subject("ansur-15936");
    po.frames = 24;
    po.seed = 2;
    po.heading_deg = heading_deg;
    return phantom::PhantomSequence::create(po);
  };
  auto facing = render(0), away = render(180);
  ASSERT_TRUE(facing.ok()) << facing.error().message;
  ASSERT_TRUE(away.ok()) << away.error().message;
  auto view_of = [](const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; };
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker tracker(facing->options().rig, CvsmOptions{});
  struct Counts {
    int person_frames = 0, tracking = 0, wrong = 0, facing_away = 0;
  };
  auto run = [&](phantom::PhantomSequence& seq) {
    Counts c;
    for (int i = 0; i < seq.frame_count(); ++i) {
      const phantom::PhantomFrame f = seq.render(i);
      const CvsmResult r = tracker.track(frontal.extract(view_of(f.luma[0])), lateral.extract(view_of(f.luma[1])));
      if (!f.truth.vertebrae) continue;
      ++c.person_frames;
      c.facing_away += r.state == TrackingState::Lost && r.fit.flag == std::string(kFacingAwayFlag);
      if (r.state != TrackingState::Tracking) continue;
      ++c.tracking;
      for (std::size_t k = 0; k < kVertebraCount; ++k)
        if ((r.vertebrae[k].body_center - (*f.truth.vertebrae)[k].body_center).norm() > test::kWrongMm) {
          ++c.wrong;
          break;
        }
    }
    return c;
  };
  const Counts first = run(*facing);
  const Counts back = run(*away);
  std::printf("facing, then back turned: tracking %d (%d wrong), then tracking %d (%d wrong), %d facing_away\n",
              first.tracking, first.wrong, back.tracking, back.wrong, back.facing_away);
  ASSERT_EQ(first.person_frames, 24);
  ASSERT_EQ(back.person_frames, 24);
  EXPECT_GE(first.tracking, 14);
  EXPECT_EQ(first.wrong, 0);
  EXPECT_EQ(back.wrong, 0);
  EXPECT_GE(back.facing_away, 20);
}

// The same render facing the frontal camera is tracked, never flagged.
TEST(CvsmHeading, TheFixedRangeTracksTheSubjectFacingTheFrontalCamera) {
  const HeadingRun run = run_turned(0, LimbMode::Fixed, HeadingRange::Fixed);
  ASSERT_EQ(run.person_frames, 24);
  EXPECT_GE(run.tracking, 14);
  EXPECT_EQ(run.wrong, 0) << "worst tracking vertebra " << run.worst_mm << " mm";
  EXPECT_EQ(run.facing_away, 0);
}

}  // namespace
}  // namespace spinewatch
