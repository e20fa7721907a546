// Articulated limbs ([cvsm] limbs = "articulated"): the joints' chain
// against a reference that composes each joint's turn about its pivot
// explicitly, and the tracker on silhouettes drawn from a model of another
// subject who raises his arms, steps and nods while bending: the
// articulated fit keeps the trunk where the fixed one is pulled off, and
// finds the limbs it can see. And the auto mode (limbs = "auto"): the
// fixed fit where the limbs are still, the arms found where they rise.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "cvsm/legs_unexplained.hpp"
#include "cvsm/lower_residual.hpp"
#include "cvsm_fixtures.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {
namespace {

// Turn about a pivot, as an isometry.
Eigen::Isometry3d turn_about(const Eigen::Vector3d& pivot, const Eigen::Matrix3d& r) {
  return Eigen::Translation3d(pivot) * Eigen::Isometry3d(r) * Eigen::Translation3d(-pivot);
}

// The reference: a plane's world point through its frame's pose and the
// chain of joints from the root down, each an explicit isometry.
Eigen::Vector3d reference_point(const BodyModel& m, const SpinePose& v, const LimbPose& limbs, std::size_t plane, int k) {
  const ControlPlane& p = m.planes[plane];
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  if (p.frame < static_cast<int>(kVertebraCount)) {
    frame = Eigen::Translation3d(v[static_cast<std::size_t>(p.frame)].body_center) * v[static_cast<std::size_t>(p.frame)].q;
  } else {
    const Eigen::Vector3d hip = p.frame == kLegLeftFrame ? m.hip_left : m.hip_right;
    frame = Eigen::Translation3d(v[kWaistIndex].body_center + v[kWaistIndex].q * hip);
  }
  Eigen::Isometry3d chain = Eigen::Isometry3d::Identity();
  for (int j = p.joint; j >= 0; j = m.joints[static_cast<std::size_t>(j)].parent)
    chain = turn_about(m.joints[static_cast<std::size_t>(j)].pivot, limb_joint_rotation(static_cast<JointId>(j), limbs)) * chain;
  return frame * (chain * m.local_points[plane * kControlPoints + static_cast<std::size_t>(k)]);
}

LimbPose random_limbs(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-60, 60);
  LimbPose l;
  for (auto& s : l.side) {
    s.shoulder_flexion = angle(rng);
    s.shoulder_abduction = angle(rng);
    s.elbow = angle(rng);
    s.hip_flexion = angle(rng);
    s.hip_abduction = angle(rng);
    s.knee = angle(rng);
  }
  l.head_flexion = angle(rng);
  l.head_lateral = angle(rng);
  l.head_turn = angle(rng);
  return l;
}

TEST(CvsmLimbs, ControlPointsFollowTheReferenceChain) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> bend_deg(-20, 40);
  for (const SubjectPosture posture : {SubjectPosture::Standing, SubjectPosture::Seated}) {
    const BodyModel m = other_subject(posture);
    for (int trial = 0; trial < 20; ++trial) {
      CvsmPose pose = bend(bend_deg(rng), bend_deg(rng) / 2, bend_deg(rng) / 3);
      pose.limbs = random_limbs(rng);
      const SpinePose v = pose_vertebrae(m, generic_spine_spec(), pose);
      std::vector<Eigen::Vector3d> pts;
      control_points(m, v, pts, pose.limbs);
      for (std::size_t p = 0; p < m.planes.size(); ++p)
        for (int k = 0; k < kControlPoints; ++k)
          ASSERT_LT((pts[p * kControlPoints + static_cast<std::size_t>(k)] - reference_point(m, v, pose.limbs, p, k)).norm(), 1e-9)
              << "plane " << p << " point " << k << " trial " << trial;
    }
  }
}

// Every plane a joint turns has one; a limb not turned is drawn bit for
// bit as without articulation, and a joint's own ring turns about its
// centre (the pivot stays put).
TEST(CvsmLimbs, OnlyTheTurnedLimbMoves) {
  const BodyModel m = other_subject();
  int arm = 0, leg = 0, head = 0;
  for (const ControlPlane& p : m.planes) {
    if (p.joint < 0) continue;
    const auto j = static_cast<JointId>(p.joint);
    arm += j == JointId::ShoulderLeft || j == JointId::ElbowLeft || j == JointId::ShoulderRight || j == JointId::ElbowRight;
    leg += j == JointId::HipLeft || j == JointId::KneeLeft || j == JointId::HipRight || j == JointId::KneeRight;
    head += j == JointId::Neck;
  }
  EXPECT_EQ(arm, 8);   // 4 rings an arm
  EXPECT_EQ(leg, 6);   // 3 a leg
  EXPECT_EQ(head, 4);  // the head above the neck's base
  const SpinePose v = pose_vertebrae(m, generic_spine_spec(), bend(20, 5, 3));
  std::vector<Eigen::Vector3d> still, raised;
  control_points(m, v, still);
  LimbPose l;
  l.side[1].shoulder_flexion = 90;  // the right arm forward
  control_points(m, v, raised, l);
  const int shoulder = static_cast<int>(JointId::ShoulderRight), elbow = static_cast<int>(JointId::ElbowRight);
  for (std::size_t p = 0; p < m.planes.size(); ++p) {
    const int j = m.planes[p].joint;
    const bool moves = j == shoulder || j == elbow;
    for (std::size_t k = 0; k < kControlPoints; ++k) {
      const std::size_t i = p * kControlPoints + k;
      if (!moves) {
        EXPECT_EQ(raised[i], still[i]) << "plane " << p;
      }
    }
  }
  // The hand ends up in front of the shoulder, near its height.
  const auto right_hand = [&](const std::vector<Eigen::Vector3d>& pts) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    std::size_t last = 0;
    for (std::size_t p = 0; p < m.planes.size(); ++p)
      if (m.planes[p].joint == elbow) last = p;
    for (std::size_t k = 0; k < kControlPoints; ++k) c += pts[last * kControlPoints + k];
    return Eigen::Vector3d(c / kControlPoints);
  };
  const Eigen::Vector3d before = right_hand(still), after = right_hand(raised);
  EXPECT_GT(after.y() - before.y(), 400);  // raised by most of the arm's length
}

struct RunErrors : SequenceErrors {
  LimbPose last_limbs;
};

CvsmOptions options_for(LimbMode limbs) {
  CvsmOptions o;
  o.spine_placement = SpinePlacementMode::Generic;
  o.limbs = limbs;
  return o;
}

RunErrors run(LimbMode limbs, const BodyModel& subject, const std::vector<CvsmPose>& poses,
              int refine_steps = CvsmOptions{}.refine_steps) {
  const CameraRig rig = CameraRig::default_rig();
  CvsmOptions options = options_for(limbs);
  options.refine_steps = refine_steps;
  CvsmTracker tracker(rig, options);
  RunErrors e;
  int frame = 0;
  static_cast<SequenceErrors&>(e) =
      track_sequence(tracker, rig, subject, poses, [&](const CvsmPose& truth, const CvsmResult& result, double neck_mm, double waist_mm) {
        ++frame;
        e.last_limbs = result.pose.limbs;
        if (std::getenv("SPINEWATCH_LIMBS_TRACE"))
          std::printf("%d neck %.1f waist %.1f cost %.3f cand %d | T %.1f/%.1f lat %.1f/%.1f tw %.1f | rsf %.0f/%.0f lab %.0f/%.0f lel %.0f/%.0f rhf %.0f/%.0f rk %.0f/%.0f hf %.0f/%.0f ht %.0f/%.0f lhf %.0f\n",
                      frame, neck_mm, waist_mm, result.fit.cost, result.fit.candidates.value_or(0), result.pose.flexion + result.pose.pelvis_flexion,
                      truth.flexion + truth.pelvis_flexion, result.pose.lateral, truth.lateral, result.pose.twist, result.pose.limbs.side[1].shoulder_flexion,
                      truth.limbs.side[1].shoulder_flexion, result.pose.limbs.side[0].shoulder_abduction, truth.limbs.side[0].shoulder_abduction,
                      result.pose.limbs.side[0].elbow, truth.limbs.side[0].elbow, result.pose.limbs.side[1].hip_flexion, truth.limbs.side[1].hip_flexion,
                      result.pose.limbs.side[1].knee, truth.limbs.side[1].knee, result.pose.limbs.head_flexion, truth.limbs.head_flexion,
                      result.pose.limbs.head_turn, truth.limbs.head_turn, result.pose.limbs.side[0].hip_flexion);
      });
  return e;
}

// Ten upright frames (the subject model), then a forward and side bend
// while the right arm rises forward, the left arm out to the side with the
// elbow bent, the right leg steps forward and the head nods and turns;
// held at the end.
std::vector<CvsmPose> reach_and_step() {
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 30; ++i) {
    const double s = std::min(1.0, i / 24.0);
    CvsmPose p = bend(25 * s, 8 * s, 0);
    p.limbs.side[1].shoulder_flexion = 90 * s;
    p.limbs.side[0].shoulder_abduction = 60 * s;
    p.limbs.side[0].elbow = 40 * s;
    p.limbs.side[1].hip_flexion = 30 * s;
    p.limbs.side[1].knee = 30 * s;
    p.limbs.head_flexion = 20 * s;
    p.limbs.head_turn = 30 * s;
    poses.push_back(p);
  }
  return poses;
}

TEST(CvsmLimbs, ArticulatedFitKeepsTheTrunkWhereTheFixedOneIsPulledOff) {
  const BodyModel subject = other_subject();
  const std::vector<CvsmPose> poses = reach_and_step();
  // The fixed limbs' own search, unrefined: the outline refinement (on by
  // default) narrows the gap (below).
  const RunErrors fixed = run(LimbMode::Fixed, subject, poses, 0);
  const RunErrors articulated = run(LimbMode::Articulated, subject, poses);
  std::printf("reach and step, fixed limbs: neck mean %.1f max %.1f, waist mean %.1f max %.1f mm, lost %d of %d\n",
              fixed.neck_mean, fixed.neck_max, fixed.waist_mean, fixed.waist_max, fixed.lost, fixed.frames);
  std::printf("reach and step, articulated: neck mean %.1f max %.1f, waist mean %.1f max %.1f mm, lost %d of %d\n",
              articulated.neck_mean, articulated.neck_max, articulated.waist_mean, articulated.waist_max,
              articulated.lost, articulated.frames);
  const LimbPose& l = articulated.last_limbs;
  std::printf("limbs at the end (truth): right shoulder flexion %.0f (90), left abduction %.0f (60), left elbow %.0f (40), "
              "right hip %.0f (30), right knee %.0f (30), head flexion %.0f (20), turn %.0f (30); left hip %.0f (0)\n",
              l.side[1].shoulder_flexion, l.side[0].shoulder_abduction, l.side[0].elbow, l.side[1].hip_flexion,
              l.side[1].knee, l.head_flexion, l.head_turn, l.side[0].hip_flexion);
  // The fixed model explains the raised arm, the step and the nod by
  // turning and bending the trunk, and loses track; the articulated one
  // keeps the trunk (measured: fixed 20.3 / 12.9 mm neck / waist mean, 11
  // of 32 pairs lost; 10.7 / 9.0 mm, 10 of 39, with provisional pairs;
  // 7.7 / 6.4 mm with the outline refinement as well, which narrows the
  // gap below these ratios; articulated 5.8–6.3 / 5.0–5.4 mm, none lost):
  // the margins are ratios.
  EXPECT_GT(fixed.lost, 3);
  EXPECT_GT(fixed.neck_mean, 1.5 * articulated.neck_mean);
  EXPECT_GT(fixed.waist_mean, 1.5 * articulated.waist_mean);
  EXPECT_EQ(articulated.lost, 0);
  EXPECT_LT(articulated.neck_mean, 10.0);
  EXPECT_LT(articulated.waist_mean, 8.0);
  EXPECT_LT(articulated.neck_max, 20.0);
  EXPECT_LT(articulated.waist_max, 20.0);
  // What both views show: the right arm raised forward, the head's nod and
  // turn. (The legs are cut at the knee's height by this rig: which one
  // stepped is not resolved; the left arm out to the side with the elbow
  // bent is not found either; docs/cvsm.md.)
  EXPECT_NEAR(l.side[1].shoulder_flexion, 90, 10);
  EXPECT_NEAR(l.head_flexion, 20, 10);
  EXPECT_NEAR(l.head_turn, 30, 10);
}

// The self-consistency bend of cvsm_test (limbs still): what articulating
// the limbs costs where they do not move.
TEST(CvsmLimbs, ArticulatedOnABendWithTheLimbsStill) {
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 40; ++i) {
    const double s = 0.5 - 0.5 * std::cos(M_PI * i / 20.0);
    poses.push_back(bend(50 * s, 12 * s, 6 * s));
  }
  const RunErrors fixed = run(LimbMode::Fixed, subject, poses);
  const RunErrors articulated = run(LimbMode::Articulated, subject, poses);
  std::printf("bend, limbs still: fixed neck %.1f waist %.1f mm; articulated neck %.1f waist %.1f mm (max %.1f / %.1f), lost %d\n",
              fixed.neck_mean, fixed.waist_mean, articulated.neck_mean, articulated.waist_mean, articulated.neck_max,
              articulated.waist_max, articulated.lost);
  // Measured: fixed 5.9 / 4.6 mm, articulated 10.4 / 10.7 mm (max 19.0 /
  // 17.7): the limbs' freedom explains some of the trunk's residual (why
  // "fixed" stays the default; docs/cvsm.md, "Articulated limbs"). It
  // still tracks the bend throughout.
  EXPECT_EQ(articulated.lost, 0);
  EXPECT_LT(articulated.neck_mean, 15.0);
  EXPECT_LT(articulated.waist_mean, 15.0);
  EXPECT_LT(articulated.neck_max, 30.0);
  EXPECT_LT(articulated.waist_max, 30.0);
}

// Auto limbs ([cvsm] limbs = "auto"): both arms raised forward and a
// little out to the side, up to 150° over 20 pairs while the trunk bends
// 15° forward, then held. The fixed fit is pulled off by the arms; the
// auto mode finds them and keeps the trunk.
std::vector<CvsmPose> arms_rising() {
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 26; ++i) {
    const double s = std::min(1.0, i / 20.0);
    CvsmPose p = bend(15 * s, 0, 0);
    for (LimbPose::Side& arm : p.limbs.side) {
      arm.shoulder_flexion = 150 * s;
      arm.shoulder_abduction = 20 * s;
    }
    poses.push_back(p);
  }
  return poses;
}

TEST(CvsmLimbs, AutoKeepsTheTrunkWhereRaisedArmsPullTheFixedFitOff) {
  const BodyModel subject = other_subject();
  const std::vector<CvsmPose> poses = arms_rising();
  const RunErrors fixed = run(LimbMode::Fixed, subject, poses);
  const RunErrors automatic = run(LimbMode::Auto, subject, poses);
  std::printf("arms rising, fixed limbs: neck mean %.1f max %.1f, waist mean %.1f max %.1f mm, lost %d of %d\n",
              fixed.neck_mean, fixed.neck_max, fixed.waist_mean, fixed.waist_max, fixed.lost, fixed.frames);
  std::printf("arms rising, auto: neck mean %.1f max %.1f, waist mean %.1f max %.1f mm, lost %d of %d; "
              "shoulders at the end %.0f / %.0f (150)\n",
              automatic.neck_mean, automatic.neck_max, automatic.waist_mean, automatic.waist_max, automatic.lost,
              automatic.frames, automatic.last_limbs.side[0].shoulder_flexion, automatic.last_limbs.side[1].shoulder_flexion);
  // The fixed fit is pulled off or loses the subject; the auto one keeps
  // the trunk within bound, tracked throughout, and holds the arms raised.
  EXPECT_TRUE(fixed.lost > 3 || fixed.neck_max > 50) << "the raised arms no longer pull the fixed fit";
  EXPECT_EQ(automatic.lost, 0);
  // (Measured: fixed 9 of 28 pairs lost; auto none, neck 4.7 / 8.5 mm
  // mean / max, waist 3.5 / 6.2, the shoulders at 160° and 154°.)
  EXPECT_LT(automatic.neck_mean, 8.0);
  EXPECT_LT(automatic.waist_mean, 8.0);
  EXPECT_LT(automatic.neck_max, 15.0);
  EXPECT_LT(automatic.waist_max, 15.0);
  EXPECT_GT(automatic.last_limbs.side[0].shoulder_flexion, 110);
  EXPECT_GT(automatic.last_limbs.side[1].shoulder_flexion, 110);
}

// Arms that rise while the subject model is still being built (four
// upright pairs, then both arms up to 150° over ten pairs): the pair that
// completes the model gets the arms' search a tracked pair gets where the
// fixed fit leaves their evidence, so it is fitted with an arm raised and
// the trunk in place, and the fit goes on from there. Without it that
// pair's fixed fit was beyond lost_cost here, and on the phantom's
// arms_overhead it completed 25762's model leaning back, 69 mm off
// (docs/cvsm.md, "Arms where the views show them"). The building's cost
// rose with the arms, so the pair itself is withheld
// (moved_while_building, docs/cvsm.md "Provisional model").
TEST(CvsmLimbs, AutoSearchesTheArmsOnThePairThatCompletesTheModel) {
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(4, CvsmPose{});
  for (int i = 0; i <= 10; ++i) {
    CvsmPose p;
    for (LimbPose::Side& arm : p.limbs.side) {
      arm.shoulder_flexion = 15.0 * i;
      arm.shoulder_abduction = 2.0 * i;
    }
    poses.push_back(p);
  }
  const CameraRig rig = CameraRig::default_rig();
  CvsmTracker tracker(rig, options_for(LimbMode::Auto));
  for (const CvsmPose& p : poses) {
    const Views v = render(rig, subject, p);
    const CvsmResult r = tracker.track(v.frontal, v.lateral);
    if (r.state == TrackingState::Init || r.provisional) continue;
    // The first pair past the provisional ones completes the model.
    const SpinePose truth = pose_vertebrae(subject, generic_spine_spec(), p);
    const double neck_mm = (r.neck - truth[kNeckIndex].body_center).norm();
    const double waist_mm = (r.waist - truth[kWaistIndex].body_center).norm();
    std::printf("the completing pair: %s, neck %.1f waist %.1f mm, shoulders %.0f / %.0f, cost %.3f\n",
                r.state == TrackingState::Tracking ? "tracking" : "lost", neck_mm, waist_mm,
                r.pose.limbs.side[0].shoulder_flexion, r.pose.limbs.side[1].shoulder_flexion, r.fit.cost);
    // Measured: lost (moved_while_building), neck 2.8 mm, waist 4.5 mm,
    // one shoulder at 70°. With the arms searched on the completing pair
    // only, after the shape had taken them in: neck 9.3, waist 22.7 mm.
    ASSERT_TRUE(r.estimated);
    EXPECT_EQ(r.state, TrackingState::Lost);
    EXPECT_EQ(r.fit.flag.value_or(""), kMovedWhileBuildingFlag);
    EXPECT_FALSE(r.pose.limbs.neutral());
    EXPECT_LT(neck_mm, 6.0);
    EXPECT_LT(waist_mm, 9.0);
    return;
  }
  FAIL() << "no pair completed the model";
}

// Where the limbs are still, the auto mode is the fixed fit: the same
// postures, bit for bit (the arms' search never engages). Unrefined: the
// outline refinement follows a search cut to its coarse steps with fixed
// limbs and the whole search with auto (docs/cvsm.md, "Outline
// refinement").
TEST(CvsmLimbs, AutoIsTheFixedFitWhereTheLimbsAreStill) {
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 24; ++i) {
    const double s = 0.5 - 0.5 * std::cos(M_PI * i / 12.0);
    poses.push_back(bend(40 * s, 10 * s, 5 * s));
  }
  const CameraRig rig = CameraRig::default_rig();
  CvsmOptions fixed_options = options_for(LimbMode::Fixed), auto_options = options_for(LimbMode::Auto);
  fixed_options.refine_steps = auto_options.refine_steps = 0;
  CvsmTracker fixed(rig, fixed_options), automatic(rig, auto_options);
  int tracked = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Views v = render(rig, subject, poses[i]);
    const CvsmResult a = fixed.track(v.frontal, v.lateral), b = automatic.track(v.frontal, v.lateral);
    ASSERT_EQ(a.state, b.state);
    tracked += a.state == TrackingState::Tracking;
    EXPECT_TRUE(b.pose.limbs.neutral());
    EXPECT_EQ(a.fit.cost, b.fit.cost);
    // The building's pairs after the first spend one evaluation more: the
    // arms' gate, the fit with the arms hanging on the model built so far
    // (building_arms).
    const int gate = i >= 1 && i < std::size_t(auto_options.subject_frames) ? 1 : 0;
    EXPECT_EQ(a.fit.candidates.value_or(0) + gate, b.fit.candidates.value_or(0)) << "pair " << i;
    for (std::size_t k = 0; k < kVertebraCount; ++k) {
      EXPECT_EQ(a.vertebrae[k].body_center, b.vertebrae[k].body_center) << "vertebra " << k;
      EXPECT_EQ(a.vertebrae[k].q.coeffs(), b.vertebrae[k].q.coeffs()) << "vertebra " << k;
    }
  }
  EXPECT_GT(tracked, 20);
}

// Auto limbs with the outline refinement on ([cvsm] refine_steps = 1, off
// by default): a pair whose fixed fit explains the views worse than the
// subject's own building pairs by the arms' evidence is not refined, since
// the refinement would pull the trunk onto the limbs' outline (docs/cvsm.md,
// "Outline refinement", gated). A long step forward from the first tracked
// pair on (the arms' search does not take it: the legs' residual), so every
// tracked pair's fixed fit is past that rise: the postures are those of the
// refinement off, bit for bit.
TEST(CvsmLimbs, AutoDoesNotRefineWhereTheLegsRaiseTheFixedFitsCost) {
  const BodyModel subject = other_subject();
  std::vector<CvsmPose> poses(10, CvsmPose{});
  for (int i = 0; i <= 14; ++i) {
    CvsmPose p = bend(1.0 * i, 0, 0);
    p.limbs.side[1].hip_flexion = 90;
    p.limbs.side[1].knee = 90;
    poses.push_back(p);
  }
  const CameraRig rig = CameraRig::default_rig();
  CvsmOptions refined_options = options_for(LimbMode::Auto);
  refined_options.refine_steps = 1;
  CvsmOptions plain_options = refined_options;
  plain_options.refine_steps = 0;
  CvsmTracker plain(rig, plain_options), refined(rig, refined_options);
  int tracked = 0;
  for (const CvsmPose& p : poses) {
    const Views v = render(rig, subject, p);
    const CvsmResult a = plain.track(v.frontal, v.lateral), b = refined.track(v.frontal, v.lateral);
    ASSERT_EQ(a.state, b.state);
    tracked += a.state == TrackingState::Tracking;
    EXPECT_EQ(a.fit.cost, b.fit.cost);
    for (std::size_t k = 0; k < kVertebraCount; ++k)
      EXPECT_EQ(a.vertebrae[k].body_center, b.vertebrae[k].body_center) << "vertebra " << k;
  }
  // (Measured: the building pairs 0.024, the tracked ones 0.134–0.146.)
  EXPECT_GT(tracked, 10);
}

// The residuals below the waist (cvsm/lower_residual.hpp) against a count
// pixel by pixel, on random masks whose rows are not whole words.
TEST(CvsmLimbs, ResidualBelowARowCountsWhatAPixelLoopCounts) {
  std::mt19937 rng(3);
  std::bernoulli_distribution on(0.4);
  for (const int width : {64, 100, 131}) {
    BitMask model(width, 37), silhouette(width, 37), hidden(width, 37);
    for (int y = 0; y < 37; ++y)
      for (int x = 0; x < width; ++x) {
        model.set(x, y, on(rng));
        silhouette.set(x, y, on(rng));
        hidden.set(x, y, on(rng));
      }
    for (const int first : {-5, 0, 11, 36, 37, 50})
      for (const BitMask* h : std::array<const BitMask*, 2>{nullptr, &hidden}) {
        std::int64_t reference = 0, outside = 0;
        for (int y = std::max(0, first); y < 37; ++y)
          for (int x = 0; x < width; ++x) {
            const bool counted = !(h && h->get(x, y));
            reference += model.get(x, y) != silhouette.get(x, y) && counted;
            outside += silhouette.get(x, y) && !model.get(x, y) && counted;
          }
        EXPECT_EQ(cvsm_detail::xor_below(model, silhouette, h, first), reference) << width << " from row " << first;
        // Only the silhouette's pixels the model misses (the legs_unexplained
        // check), not the model's the silhouette lacks.
        EXPECT_EQ(cvsm_detail::silhouette_outside_below(model, silhouette, h, first), outside)
            << width << " from row " << first;
        if (first <= 0) {
          EXPECT_LT(outside, reference);
        }
      }
  }
}

// The legs_unexplained check (cvsm/legs_unexplained.hpp) needs all three:
// legs outside the model, a lean over them, a fit off its baseline; any
// one alone is ordinary (a stride followed, a side bend, raised arms).
TEST(CvsmLimbs, LegsAreUnexplainedOnlyWithALeanAndACostRise) {
  const cvsm_detail::LegsEvidence all{0.09, 12, 0.15};
  EXPECT_TRUE(cvsm_detail::legs_unexplained(all));
  cvsm_detail::LegsEvidence e = all;
  e.outside_share = cvsm_detail::kLegsOutsideShare;
  EXPECT_FALSE(cvsm_detail::legs_unexplained(e));
  e = all;
  e.lean_deg = 0.99 * cvsm_detail::kLegsLeanDeg;
  EXPECT_FALSE(cvsm_detail::legs_unexplained(e));
  e = all;
  e.cost_rise = cvsm_detail::kLegsCostRise;
  EXPECT_FALSE(cvsm_detail::legs_unexplained(e));
}

}  // namespace
}  // namespace spinewatch
