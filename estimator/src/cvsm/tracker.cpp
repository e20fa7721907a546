#include "spinewatch/estimator/cvsm/tracker.hpp"

#include <algorithm>
#include <cmath>

#include "cvsm/coordinate_search.hpp"
#include "cvsm/facing_check.hpp"
#include "cvsm/legs_region.hpp"
#include "cvsm/legs_unexplained.hpp"
#include "cvsm/lower_residual.hpp"
#include "cvsm/occluder_edge.hpp"
#include "cvsm/outline_fit.hpp"
#include "cvsm/pelvis_in_view.hpp"
#include "cvsm/subject_estimate.hpp"
#include "cvsm/subject_heading.hpp"
#include "cvsm/xor_cost.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {

using cvsm_detail::coordinate_descent;

namespace {

// The search's parameters: total trunk flexion T (spine and pelvis
// together, a third of it in the pelvis as in a natural forward bend),
// lateral, twist, the pelvis's share beyond that third, pelvis lateral and
// the translation. A bend then moves along one parameter instead of two,
// and the residual only settles how it is shared.
using PoseParams = std::array<double, 8>;  // T, lateral, twist, pelvis residual, pelvis lateral, tx, ty, tz
constexpr double kPelvisShare = 1.0 / 3.0;

// The options without the worker's given body (stature, landmarks, mass):
// for a subject whose given stature the views contradicted.
CvsmOptions without_given_body(CvsmOptions o) {
  o.stature_mm.reset();
  o.c7_height_mm.reset();
  o.iliac_crest_height_mm.reset();
  o.mass_kg.reset();
  return o;
}
PoseParams to_params(const CvsmPose& p) {
  const double total = p.flexion + p.pelvis_flexion;
  return {total, p.lateral, p.twist, p.pelvis_flexion - kPelvisShare * total, p.pelvis_lateral,
          p.translation.x(), p.translation.y(), p.translation.z()};
}
CvsmPose to_pose(const PoseParams& a, const LimbPose& limbs) {
  CvsmPose p;
  p.limbs = limbs;
  p.pelvis_flexion = kPelvisShare * a[0] + a[3];
  p.flexion = a[0] - p.pelvis_flexion;
  p.lateral = a[1];
  p.twist = a[2];
  p.pelvis_lateral = a[4];
  p.translation = {a[5], a[6], a[7]};
  return p;
}

// The limbs' search parameters, in degrees: per side (left, right) the
// shoulder's flexion and abduction and the elbow, the hip's flexion and
// abduction and the knee; then the head's flexion, lateral tilt and turn.
constexpr std::size_t kLimbParams = 15;
using LimbParams = std::array<double, kLimbParams>;

LimbParams to_limb_params(const LimbPose& l) {
  LimbParams a{};
  for (std::size_t s = 0; s < 2; ++s) {
    const LimbPose::Side& d = l.side[s];
    const std::size_t o = 6 * s;
    a[o + 0] = d.shoulder_flexion;
    a[o + 1] = d.shoulder_abduction;
    a[o + 2] = d.elbow;
    a[o + 3] = d.hip_flexion;
    a[o + 4] = d.hip_abduction;
    a[o + 5] = d.knee;
  }
  a[12] = l.head_flexion;
  a[13] = l.head_lateral;
  a[14] = l.head_turn;
  return a;
}
LimbPose to_limbs(const LimbParams& a) {
  LimbPose l;
  for (std::size_t s = 0; s < 2; ++s) {
    LimbPose::Side& d = l.side[s];
    const std::size_t o = 6 * s;
    d.shoulder_flexion = a[o + 0];
    d.shoulder_abduction = a[o + 1];
    d.elbow = a[o + 2];
    d.hip_flexion = a[o + 3];
    d.hip_abduction = a[o + 4];
    d.knee = a[o + 5];
  }
  l.head_flexion = a[12];
  l.head_lateral = a[13];
  l.head_turn = a[14];
  return l;
}

// Where each angle may go from the model's neutral limbs (arms hanging,
// elbows a little flexed; legs hanging or seated), degrees: the joints'
// active ranges, so the search cannot fold a limb through the body.
constexpr std::array<std::array<double, 2>, kLimbParams> kLimbRange{{
    {-60, 180}, {-20, 170}, {-20, 140}, {-30, 120}, {-20, 60}, {-5, 140},  // left
    {-60, 180}, {-20, 170}, {-20, 140}, {-30, 120}, {-20, 60}, {-5, 140},  // right
    {-40, 45}, {-30, 30}, {-80, 80}}};                                      // head
bool in_range(const LimbParams& a) {
  for (std::size_t i = 0; i < kLimbParams; ++i)
    if (a[i] < kLimbRange[i][0] || a[i] > kLimbRange[i][1]) return false;
  return true;
}

// The model with the arms' chains left out (their planes stay, unused).
BodyModel without_arms(const BodyModel& model) {
  BodyModel m = model;
  std::erase_if(m.chains, [&](const std::vector<int>& chain) {
    const int j = model.planes[static_cast<std::size_t>(chain.front())].joint;
    return j == static_cast<int>(JointId::ShoulderLeft) || j == static_cast<int>(JointId::ShoulderRight);
  });
  m.in_chain.assign(m.planes.size(), 0);
  for (const auto& chain : m.chains)
    for (const int p : chain) m.in_chain[static_cast<std::size_t>(p)] = 1;
  return m;
}

}  // namespace

// Where the tracker stands between two pairs. Transitions (track(), no_person()):
//   Building   --a clean pair refines the model; from the
//                 provisional_frames-th on it is published as
//                 tracking (publish_provisional)--> Building
//   Building   --the subject_frames-th clean pair
//                 completes the model-->          Tracking (fit within lost_cost)
//                                                 or Searching (fit beyond it)
//   Building   --no person, or a flagged pair-->  Building (nothing learnt)
//   Searching  --global search, good fit-->       Predicting (clean pair) or Tracking (flagged pair)
//   Tracking,
//   Predicting --local search, good fit-->        Predicting (clean pair) or Tracking (flagged pair)
//   Searching, Tracking,
//   Predicting --fit beyond lost_cost-->          Searching
//   Searching, Tracking,
//   Predicting --no person-->                     Searching
// Nothing leads back to Building but reset().
enum class Phase : std::uint8_t {
  Building,    // the subject model is not complete (init_frames < subject_frames, or none yet): state init,
               // or tracking from provisional_frames on (CvsmResult::provisional)
  Searching,   // the model is built, the pose is not known: the next pair is searched for globally
  Tracking,    // the last fit was good: a local search from it
  Predicting,  // as Tracking, and the pair before was good and clean too: the local search also
               // tries the constant-velocity prediction from `previous`
};

struct CvsmTracker::Impl {
  CameraRig rig;
  CvsmOptions opt;
  CvsmSpec spec;
  SpineSpec spine;
  std::unique_ptr<XorCost> cost;
  std::vector<Eigen::Vector3d> points;

  std::optional<cvsm_detail::SubjectEstimate> subject;  // during init and after
  BodyModel model;
  BodyModel search_model;  // the model the tracked search compares candidates on
  // Articulated limbs: the search model without its arms, which the
  // trunk's own search compares on (the arms' outline, wherever they are,
  // then does not turn the trunk), and which one `evaluate_on` points at.
  BodyModel armless_model;
  const BodyModel* trunk_search_model = &search_model;
  Phase phase = Phase::Building;
  int init_frames = 0;  // pairs built into the model; a model exists once it is 1
  CvsmPose pose, previous;  // `previous`: the pose before `pose`, meaningful in Predicting only
  Eigen::Vector3d home = Eigen::Vector3d::Zero();  // the translation the subject model was built at

  Impl(const CameraRig& r, CvsmOptions o)
      : rig(r),
        opt(std::move(o)),
        spec(opt.model ? *opt.model : generic_cvsm_spec()),
        spine(opt.spine ? *opt.spine : generic_spine_spec()) {}

  XorCounts evaluate(const BodyModel& m, const CvsmPose& p, std::int64_t limit) {
    const SpinePose v = pose_vertebrae(m, spine, p);
    control_points(m, v, points, p.limbs, p.heading);
    return cost->evaluate(m, points, limit);
  }
  // The pose with these trunk parameters and the limbs held where they are.
  // The heading, too, is held: it has a search of its own (follow_heading).
  CvsmPose trunk_pose(const PoseParams& a) const {
    CvsmPose p = to_pose(a, pose.limbs);
    p.heading = pose.heading;
    return p;
  }

  // The hip joints stay where the subject stood or sat: moving them is
  // charged in pixels, so a bend is explained by the spine and pelvis
  // rather than by sliding the whole body (the outline alone barely tells
  // a pelvis tilt from a forward shift). Quadratic, so the few millimetres
  // of sway cost next to nothing and a real step still wins.
  // 0.5 px/mm²: 10 mm cost 50 pixels, 30 mm 450 (a whole-body outline
  // shift of 30 mm leaves well over a thousand XOR pixels). The global
  // search looks everywhere, unanchored; when it finds the subject a real
  // step away (kNewHomeMm), that is where the subject now stands.
  static constexpr double kTranslationPxPerMm2 = 0.5;
  static constexpr double kNewHomeMm = 50;
  bool anchored = true;
  // In the cost's sampled pixels.
  double translation_penalty(const PoseParams& a) const {
    if (!anchored) return 0;
    const double d2 = (Eigen::Vector3d(a[5], a[6], a[7]) - home).squaredNorm();
    return kTranslationPxPerMm2 * d2 / cost->row_step();
  }

  // A limb the views cannot see (hidden behind the trunk, beyond the
  // image's border) leaves the XOR flat along its angles: this small pull
  // towards the neutral limbs settles it there instead of wherever the
  // search last left it, and a limb that is seen outweighs it many times
  // (an arm raised 60° moves some 200 search pixels; the pull costs 18).
  // In the cost's sampled pixels, per degree².
  static constexpr double kLimbPxPerDeg2 = 0.02;
  double limb_penalty(const LimbPose& limbs) const {
    if (opt.limbs == LimbMode::Fixed) return 0;
    double sum = 0;
    for (const double a : to_limb_params(limbs)) sum += a * a;
    return kLimbPxPerDeg2 * sum / cost->row_step();
  }

  std::int64_t cost_of(const PoseParams& a, std::int64_t limit) { return cost_of(trunk_pose(a), a, limit); }
  std::int64_t cost_of(const CvsmPose& p, const PoseParams& a, std::int64_t limit) {
    const auto penalty = static_cast<std::int64_t>(translation_penalty(a) + limb_penalty(p.limbs));
    if (penalty >= limit) return penalty;
    return evaluate(*trunk_search_model, p, limit - penalty).total() + penalty;
  }

  // The best of the candidates tried so far, each pruned against it.
  struct Candidates {
    Impl& impl;
    PoseParams best;
    std::int64_t best_cost;
    int evaluations = 1;
    Candidates(Impl& i, const PoseParams& start) : impl(i), best(start), best_cost(i.cost_of(start, INT64_MAX)) {}
    void try_one(const PoseParams& a) {
      ++evaluations;
      const std::int64_t c = impl.cost_of(a, best_cost);
      if (c < best_cost) {
        best_cost = c;
        best = a;
      }
    }
  };

  // Local coarse-to-fine search around `start` (and a constant-velocity
  // prediction from it).
  int local_search(int budget) {
    Candidates c(*this, to_params(pose));
    if (phase == Phase::Predicting) {
      PoseParams predicted = c.best, prev = to_params(previous);
      for (std::size_t i = 0; i < predicted.size(); ++i) predicted[i] += c.best[i] - prev[i];
      c.try_one(predicted);
    }
    // From the prediction the residual motion is small: a 2° / 5 mm step,
    // then a half step only for what moved.
    const PoseParams step{2, 2, 2, 2, 1, 5, 3, 5};
    auto d = coordinate_descent(c.best, c.best_cost, step, 2, budget - c.evaluations,
                                [&](const PoseParams& a, std::int64_t limit) { return cost_of(a, limit); }, true);
    pose = trunk_pose(d.params);
    searched_cost = d.best;
    return c.evaluations + d.evaluations;
  }
  std::int64_t searched_cost = INT64_MAX;  // local_search's result's

  // The articulated limbs, with the trunk held where its search left it:
  // probes of each angle, then a coordinate descent over the fifteen
  // (steps `step_deg`, then halved, only for what moved; `budget`
  // evaluations beyond the probes). Returns the evaluations spent.
  static constexpr std::array<double, 4> kLimbProbesDeg{20, -20, 10, -10};
  int limb_search(int budget, double step_deg, int levels) {
    if (!searching_limbs() || budget <= 0) return 0;
    const PoseParams trunk = to_params(pose);
    CvsmPose candidate = pose;
    auto limb_cost = [&](const LimbParams& l, std::int64_t limit) -> std::int64_t {
      if (!in_range(l)) return INT64_MAX;
      candidate.limbs = to_limbs(l);
      return cost_of(candidate, trunk, limit);
    };
    LimbParams best = to_limb_params(pose.limbs);
    std::int64_t best_cost = limb_cost(best, INT64_MAX);
    int evaluations = 1;
    // A limb is thin: its XOR falls only within about its own width of
    // where it is (an arm 50 px long and 8 px wide: ±9°), and between
    // there and where the model holds it, it may rise. So each angle first
    // probes farther out, keeping the best, then the descent settles it.
    for (std::size_t i = 0; i < kLimbParams; ++i)
      for (const double probe : kLimbProbesDeg) {
        if (!searched_limb(i)) continue;
        LimbParams trial = best;
        trial[i] += probe;
        ++evaluations;
        const std::int64_t c = limb_cost(trial, best_cost);
        if (c < best_cost) {
          best_cost = c;
          best = trial;
        }
      }
    evaluations += place_arms(best, best_cost, limb_cost);
    LimbParams step;
    for (std::size_t i = 0; i < kLimbParams; ++i) step[i] = searched_limb(i) ? step_deg : 0;
    auto d = coordinate_descent(best, best_cost, step, levels, budget, limb_cost, true);
    pose.limbs = to_limbs(d.params);
    return evaluations + d.evaluations;
  }

  // The trunk again, the limbs held where their search left them: half
  // the tracked search's steps, one level. Returns the evaluations spent.
  int joint_refinement(int budget) {
    if (!searching_limbs() || budget <= 0) return 0;
    const PoseParams start = to_params(pose);
    const std::int64_t start_cost = cost_of(start, INT64_MAX);
    const PoseParams step{1, 1, 1, 1, 0.5, 2.5, 1.5, 2.5};
    auto d = coordinate_descent(start, start_cost, step, 1, budget - 1,
                                [&](const PoseParams& a, std::int64_t limit) { return cost_of(a, limit); });
    pose = trunk_pose(d.params);
    return 1 + d.evaluations;
  }

  // The searches compare candidates on whole pixels, so the pose they
  // return rests on whichever stair of that cost their path reached; this
  // settles it between them on the outline (outline_fit.hpp). Derivatives
  // over a quarter of a search step; a step moves a parameter at most one
  // search step (2°; 5 / 3 / 5 mm).
  std::array<cvsm_detail::SilhouetteEdges, 2> edges;
  // Not with articulated limbs: there the limbs' search, started from the
  // refined trunk, no longer finds a raised arm (CvsmLimbs.ArticulatedFit…:
  // the right shoulder at −16° for the truth's 90°), and the trunk's search
  // keeps its whole budget.
  bool refining() const {
    return opt.refine_steps > 0 && (opt.limbs == LimbMode::Fixed || (opt.limbs == LimbMode::Auto && !arms_pass));
  }
  // The fixed fit, refined where its outline is the model's: with auto
  // limbs, only where it explains the views as the subject's own building
  // pairs did (below the arms' evidence, kArmsEvidenceRise). Where raised
  // arms or moving legs raise the cost, the refinement pulls the trunk onto
  // the limbs' outline, and the search keeps its whole budget since the
  // refinement may not follow. An experiment: whole varied phantom,
  // refine_steps = 1, tracking postures over 50 mm without / with this gate
  // and the whole budget: stride 12 → 1, lunge 33 → 31, cluttered room
  // 0 → 3, camera tilt 45° 3 → 3 (docs/cvsm.md, "Outline refinement"; the
  // refinement stays off by default).
  CvsmResult settle(const BitMask& frontal, const BitMask& lateral, int candidates, std::string_view flag,
                    bool searched_globally) {
    if (!refining()) return finish(TrackingState::Tracking, candidates, flag);
    if (opt.limbs == LimbMode::Auto) {
      CvsmResult searched = finish(TrackingState::Tracking, candidates, flag);
      if (!refine_follows(searched.fit.cost)) return searched;
      ++candidates;  // that evaluation
    }
    anchored = !searched_globally;  // refined as it was searched
    candidates += refine(frontal, lateral, opt.refine_steps);
    anchored = true;
    return finish(TrackingState::Tracking, candidates, flag);
  }
  bool refine_follows(double fixed_cost) const { return fixed_cost < best_building_cost + kArmsEvidenceRise; }
  int refine(const BitMask& frontal, const BitMask& lateral, int steps) {
    if (steps <= 0) return 0;
    cost->set_row_step(opt.refine_row_step);
    edges[0].assign(frontal);
    edges[1].assign(lateral);
    cvsm_detail::OutlineFitSettings settings;
    settings.probe = {0.5, 0.5, 0.5, 0.5, 0.5, 1, 1, 1};
    settings.max_step = {2, 2, 2, 2, 2, 5, 3, 5};
    settings.shifts_along = {-1, -1, -1, -1, -1, 0, 1, 2};  // the translation (pose_vertebrae)
    cvsm_detail::OutlineFit fit(*cost, model, {&edges[0], &edges[1]}, cost_width, settings);
    cvsm_detail::ParamPrior prior;
    if (anchored)
      for (std::size_t k = 5; k < 8; ++k) {
        prior.weight[k] = kTranslationPxPerMm2 / cost->row_step();  // translation_penalty's
        prior.centre[k] = home[static_cast<Eigen::Index>(k - 5)];
      }
    PoseParams a = to_params(pose);
    const int scans = fit.refine(a, steps, [&](const PoseParams& p, std::vector<Eigen::Vector3d>& out) {
      control_points(model, pose_vertebrae(model, spine, trunk_pose(p)), out, pose.limbs, pose.heading);
    }, prior);
    pose = trunk_pose(a);
    return scans;
  }

  // The heading per tracked pair: one step either way from where it was
  // (a person turns a few degrees between pairs), kept when it fits
  // better by more than four times the pair-to-pair noise of the cost
  // (kHeadingMarginFraction): a few degrees of heading and of axial
  // twist draw nearly the same outline, and the heading must not follow
  // the twist. Two evaluations.
  static constexpr double kHeadingStepDeg = 2;
  std::int64_t silhouette_px = 0;  // both views of the current pair, whole pixels
  int follow_heading(std::int64_t current_cost) {
    if (opt.heading == HeadingRange::Fixed) return 0;
    const PoseParams a = to_params(pose);
    const auto gain = static_cast<std::int64_t>(cvsm_detail::kHeadingMarginFraction * static_cast<double>(silhouette_px) / cost->row_step());
    std::int64_t best = current_cost - gain;
    const double start = pose.heading;
    for (const double step : {kHeadingStepDeg, -kHeadingStepDeg}) {
      if (!cvsm_detail::heading_allowed(opt.heading, start + step)) continue;
      CvsmPose trial = pose;
      trial.heading = cvsm_detail::wrapped_heading(start + step);
      const std::int64_t c = cost_of(trial, a, best);
      if (c < best) {
        best = c;
        pose = trial;
      }
    }
    // A turn off the preferred heading (facing the frontal camera, or over
    // the full circle the back to it) is kept only while it wins by the
    // preference for it (subject_heading.hpp), judged every pair.
    const double preferred = cvsm_detail::preferred_heading(opt.heading, pose.heading);
    if (cvsm_detail::wrapped_heading(pose.heading) != preferred) {
      CvsmPose facing = pose;
      facing.heading = preferred;
      const std::int64_t facing_cost = cost_of(facing, a, INT64_MAX);
      const std::int64_t turned_cost = best < current_cost - gain ? best : current_cost;
      if (turned_cost >= cvsm_detail::cost_to_beat_facing(opt.heading, pose.heading, facing_cost,
                                                          static_cast<std::int64_t>(static_cast<double>(silhouette_px) / cost->row_step())))
        pose = facing;
      return 3;
    }
    return 2;
  }

  // A step aside (docs/cvsm.md, "A step aside"): the body moves with the
  // feet, but the local search is held back twice — by the anchor (a step
  // of 100 mm costs 5000 pixels) and by the template's straight, closed
  // legs, whose outline keeps the pelvis over the leg that stood still.
  // So, with the trunk near upright, the pose is searched again with the
  // legs not counted (below the hips in both views) and unanchored, from
  // the trunk straightened where it stands: translation first in wide
  // steps, then every parameter. It replaces the local search's pose, and
  // becomes the new home, only when it moved the body a step
  // (kStepMinMm, more than the anchor lets sway — up, down or across: a
  // lunge lowers the pelvis) and fits the outline above
  // the hips better by more than the cost's pair-to-pair noise
  // (kStepMarginFraction, as the heading's margin). Not when bent forward
  // (kStepUprightDeg): in a view that looks down, the bent trunk projects
  // below the hips. About 60 evaluations. With the legs held straight
  // ("fixed", and "auto"'s fixed fit) only: with articulated limbs it also
  // followed the steps, but added confidently wrong postures in the
  // cluttered room (docs/cvsm.md, "A step aside").
  static constexpr double kStepMinMm = 20;
  static constexpr double kStepMarginFraction = cvsm_detail::kHeadingMarginFraction;
  static constexpr double kStepUprightDeg = 15;
  // Only where the local search bent the trunk sideways: a step drawn by
  // closed legs comes out as a side bend over hips that stayed (stride,
  // 28496: 39°), and a twisting or swaying subject was otherwise moved by
  // it (the exposure shift's twists: 7.87 s over 60° read as 6.07 s).
  static constexpr double kStepSideBendDeg = 8;
  std::array<BitMask, 2> legs_hidden;
  int follow_step() {
    const PoseParams a = to_params(pose);
    if (opt.limbs == LimbMode::Articulated || std::abs(a[0]) > kStepUprightDeg || std::abs(a[1]) < kStepSideBendDeg)
      return 0;
    const SpinePose v = pose_vertebrae(model, spine, pose);
    cvsm_detail::hide_below_hips(rig.frontal, model, v, hiding[0] ? &hidden[0] : nullptr, cost_width, cost_height, legs_hidden[0]);
    cvsm_detail::hide_below_hips(rig.lateral, model, v, hiding[1] ? &hidden[1] : nullptr, cost_width, cost_height, legs_hidden[1]);
    cost->set_hidden(&legs_hidden[0], &legs_hidden[1]);
    anchored = false;
    auto trunk_cost = [&](const PoseParams& q, std::int64_t limit) { return cost_of(q, limit); };
    const std::int64_t searched = cost_of(a, INT64_MAX);
    PoseParams straight = a;
    straight[1] = straight[4] = 0;  // no side bend or pelvis tilt; the twist kept (a twist is not a step)
    const auto moved = coordinate_descent(straight, cost_of(straight, INT64_MAX), PoseParams{0, 0, 0, 0, 0, 40, 0, 40}, 3, 24, trunk_cost);
    const auto settled = coordinate_descent(moved.params, moved.best, PoseParams{4, 4, 4, 4, 2, 10, 6, 10}, 3, 60, trunk_cost);
    anchored = true;
    cost->set_hidden(hiding[0] ? &hidden[0] : nullptr, hiding[1] ? &hidden[1] : nullptr);
    const auto margin = static_cast<std::int64_t>(kStepMarginFraction * static_cast<double>(silhouette_px) / cost->row_step());
    const double step_mm = std::hypot(settled.params[5] - a[5], settled.params[6] - a[6], settled.params[7] - a[7]);
    // A step explains the local search's side bend away; a pose that keeps
    // most of it is a side bend (with a twist, a sway), not a step.
    const bool bend_explained = std::abs(settled.params[1]) < 0.5 * std::abs(a[1]);
    if (settled.best + margin < searched && step_mm > kStepMinMm && bend_explained) {
      pose = trunk_pose(settled.params);
      home = pose.translation;
    }
    return 2 + moved.evaluations + settled.evaluations;
  }

  // At (re)acquisition the subject may have turned any way: the full
  // circle, every kHeadingProbeDeg, at the upright trunk where the subject
  // was last; the global search then starts from the best.
  // Sets heading_resolved: whether the best heading beat every heading
  // 90° or more from it by choose_heading's margin.
  int probe_headings() {
    if (opt.heading == HeadingRange::Fixed) return 0;
    CvsmPose upright = pose;
    upright.flexion = upright.lateral = upright.twist = upright.pelvis_flexion = upright.pelvis_lateral = 0;
    struct Probe {
      CvsmPose pose;
      std::int64_t cost;
    };
    std::vector<Probe> probes;
    std::size_t best = 0;
    for (const double h : cvsm_detail::heading_probes(opt.heading, pose.heading)) {
      const CvsmPose trial = cvsm_detail::turned_in_place(model, spine, upright, h);
      probes.push_back({trial, cost_of(trial, to_params(trial), INT64_MAX)});
      if (probes.back().cost < probes[best].cost) best = probes.size() - 1;
    }
    // The silhouettes' pixels, whatever the pose.
    const XorCounts counts = evaluate(*trunk_search_model, probes[best].pose, INT64_MAX);
    const std::int64_t silhouette_px = counts.silhouette_px[0] + counts.silhouette_px[1];
    // The front range prefers facing the frontal camera (subject_heading.hpp).
    for (std::size_t i = 0; i < probes.size(); ++i)
      if (cvsm_detail::wrapped_heading(probes[i].pose.heading) ==
              cvsm_detail::preferred_heading(opt.heading, probes[best].pose.heading) &&
          probes[best].cost >=
              cvsm_detail::cost_to_beat_facing(opt.heading, probes[best].pose.heading, probes[i].cost, silhouette_px))
        best = i;
    std::int64_t other_side = INT64_MAX;
    for (const Probe& p : probes)
      if (cvsm_detail::heading_apart(p.pose.heading, probes[best].pose.heading) >= 90) other_side = std::min(other_side, p.cost);
    cvsm_detail::HeadingChoice choice;
    choice.margin_px = other_side - probes[best].cost;
    choice.silhouette_px = silhouette_px;
    heading_resolved = choice.resolved();
    pose = probes[best].pose;
    return static_cast<int>(probes.size()) + 1;
  }

  // Whole-range search over trunk flexion and lateral bending, then a wide
  // local search.
  int global_search(int budget) {
    PoseParams base = to_params(pose);
    base[0] = base[1] = base[2] = base[3] = base[4] = 0;
    Candidates c(*this, base);
    for (double f = -20; f <= 80; f += 10)
      for (double l = -30; l <= 30; l += 10) {
        PoseParams a = base;
        a[0] = f;
        a[1] = l;
        c.try_one(a);
      }
    const PoseParams step{8, 6, 8, 6, 4, 40, 20, 40};
    auto d = coordinate_descent(c.best, c.best_cost, step, 6, budget - c.evaluations,
                                [&](const PoseParams& a, std::int64_t limit) { return cost_of(a, limit); });
    pose = trunk_pose(d.params);
    return c.evaluations + d.evaluations;
  }

  // Axial twist: the two views see its magnitude (a twisted thorax and the
  // arms hanging from it narrow the frontal outline and spread the lateral
  // one) far better than its sign: under a parallel projection a twist of
  // +θ and −θ draw the same pair of outlines, and only perspective (the
  // nearer shoulder larger), the forearms reaching forward and the trunk's
  // front/back asymmetry about the spine tell them apart. So once a search
  // settles on a twist of kTwistSignatureDeg or more, the mirrored twist
  // (every other parameter kept) is scored too: the better of the two is
  // kept, and when they score within kTwistSignMarginPx the sign is not
  // resolved and the pair is flagged "twist_unresolved" (docs/cvsm.md,
  // "Axial twist"). Two evaluations, on the search's rows.
  static constexpr double kTwistSignatureDeg = 6;
  static constexpr std::int64_t kTwistSignMarginPx = 40;
  struct TwistCheck {
    bool checked = false;
    std::int64_t margin_px = 0;  // mirrored twist's cost − the kept one's, ≥ 0
    bool resolved() const { return !checked || margin_px >= kTwistSignMarginPx; }
  };
  TwistCheck check_twist_sign(int& candidates) {
    TwistCheck t;
    const PoseParams a = to_params(pose);
    if (std::abs(a[2]) < kTwistSignatureDeg) return t;
    PoseParams mirrored = a;
    mirrored[2] = -a[2];
    const std::int64_t kept = cost_of(a, INT64_MAX), other = cost_of(mirrored, INT64_MAX);
    candidates += 2;
    t.checked = true;
    if (other < kept) pose = trunk_pose(mirrored);
    t.margin_px = std::abs(other - kept);
    return t;
  }

  // Auto limbs (docs/cvsm.md, "Arms where the views show them"): the fixed
  // fit, and the arms' search only where that fit leaves more of the
  // silhouettes unexplained than the subject's own baseline (the best fit
  // of the model's building pairs) by kArmsEvidenceRise, or where the arms
  // were raised at the pair before. The arms' fit is then kept only when
  // it explains kArmsGain of the silhouettes' pixels more than the fixed
  // fit; else the fixed fit stands as it was found. Ratios of the
  // silhouettes' pixels (the reported cost).
  static constexpr double kArmsEvidenceRise = 0.1;
  static constexpr double kArmsGain = 0.02;
  // ... and only when the arms' fit leaves at most this share of the
  // silhouettes unexplained below the waist: above it the legs moved,
  // which the arms cannot explain (on the development subject, 28496:
  // 0.009–0.057 with the arms overhead but for one pair of 0.080, 0.083–
  // 0.17 in a lunge, 0.11–0.24 in a stride).
  static constexpr double kArmsLowerResidualMax = 0.06;
  // Where an arm is engaged from hanging, each shoulder angle is also
  // tried at these angles: a raised arm is found wherever it is (the
  // probes' ±20° from hanging find only an arm that has just begun).
  static constexpr std::array<double, 4> kArmPlacementsDeg{45, 90, 135, 170};
  bool arms_pass = false;  // the arms' search of the auto mode is running
  bool wide_arms = false;  // ... and it starts from hanging arms
  bool searching_limbs() const { return opt.limbs == LimbMode::Articulated || arms_pass; }
  // Which of the limbs' parameters the search moves: all of them, or in
  // the auto mode the arms' (the shoulders' two angles and the elbow).
  bool searched_limb(std::size_t i) const { return opt.limbs == LimbMode::Articulated || (i < 12 && i % 6 < 3); }
  template <class LimbCost>
  int place_arms(LimbParams& best, std::int64_t& best_cost, LimbCost& limb_cost) {
    if (!wide_arms) return 0;
    int evaluations = 0;
    for (const std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{6}, std::size_t{7}})
      for (const double angle : kArmPlacementsDeg) {
        LimbParams trial = best;
        trial[i] = angle;
        ++evaluations;
        const std::int64_t c = limb_cost(trial, best_cost);
        if (c < best_cost) {
          best_cost = c;
          best = trial;
        }
      }
    return evaluations;
  }
  // The share of both silhouettes' pixels the fit at `points` leaves
  // unexplained below the waist's row in each view (lower_residual.hpp):
  // where the two differ, or only the silhouette's pixels the model misses.
  enum class BelowWaist { Xor, SilhouetteOutside };
  double residual_below_waist(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r,
                              BelowWaist what = BelowWaist::Xor) {
    const BitMask* masks[2] = {&frontal, &lateral};
    const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
    std::int64_t n = 0;
    for (std::size_t v = 0; v < 2; ++v) {
      const std::optional<Eigen::Vector2d> waist = cams[v]->project(r.waist);
      if (!waist) continue;
      const BitMask drawn = cost->render(model, points, v == 0 ? View::Frontal : View::Lateral);
      const BitMask* h = hiding[v] ? &hidden[v] : nullptr;
      const int row = static_cast<int>(std::ceil(waist->y()));
      n += what == BelowWaist::SilhouetteOutside ? cvsm_detail::silhouette_outside_below(drawn, *masks[v], h, row)
                                                 : cvsm_detail::xor_below(drawn, *masks[v], h, row);
    }
    return static_cast<double>(n) / static_cast<double>(std::max<std::int64_t>(1, silhouette_px));
  }
  void try_arms(CvsmResult& r, TwistCheck& twist, const CvsmPose& before, bool searched_globally, std::string_view flag,
                const BitMask& frontal, const BitMask& lateral) {
    const bool engaged = !before.limbs.neutral();
    if (!engaged && r.fit.cost < best_building_cost + kArmsEvidenceRise) return;
    const CvsmPose fixed_pose = pose;
    const CvsmResult fixed = r;
    arms_pass = true;
    wide_arms = !engaged || searched_globally;  // the arms hanging where the search starts
    cost->set_row_step(opt.search_row_step);
    int candidates = 0;
    if (searched_globally) {
      // Found again by the fixed fit: the arms from hanging, in wide steps.
      candidates += limb_search(2 * opt.limb_budget, 8, 3);
    } else {
      // The trunk by the trunk's outline, from where it was; then the arms.
      pose = before;
      pose.heading = fixed_pose.heading;
      trunk_search_model = &armless_model;
      candidates += local_search(opt.local_budget);
      trunk_search_model = &search_model;
      candidates += limb_search(opt.limb_budget, 4, 2);
    }
    candidates += joint_refinement(opt.joint_budget);
    TwistCheck arms_twist = check_twist_sign(candidates);
    arms_pass = wide_arms = false;
    CvsmResult armed = finish(TrackingState::Tracking, fixed.fit.candidates.value_or(0) + candidates, flag);
    // The gain must be the arms': the same trunk with the arms hanging
    // explains kArmsGain less (a guard: no phantom row came out otherwise
    // without it). And what the legs drew must be explained: a step or a
    // lunge also raises the fixed fit's cost, and the arms and the armless
    // trunk lower it (lunge 35 → 86 confidently wrong without this check).
    const double below = residual_below_waist(frontal, lateral, armed);
    CvsmPose hanging = pose;
    hanging.limbs = {};
    const double hanging_cost = evaluate(model, hanging, INT64_MAX).cost();
    if (armed.fit.cost <= fixed.fit.cost - kArmsGain && armed.fit.cost <= hanging_cost - kArmsGain &&
        below <= kArmsLowerResidualMax) {
      r = armed;
      r.fit.candidates = armed.fit.candidates.value_or(0) + 1;
      twist = arms_twist;
    } else {
      // The fixed fit stands, as found (the work done counted).
      pose = fixed_pose;
      r = fixed;
      r.fit.candidates = fixed.fit.candidates.value_or(0) + candidates + 1;
    }
    // The reported pose's points (fitted_mask()).
    control_points(model, pose_vertebrae(model, spine, pose), points, pose.limbs, pose.heading);
  }

  CvsmResult finish(TrackingState state, int candidates, std::string_view flag) {
    CvsmResult r;
    cost->set_row_step(1);  // the reported figures are whole-image pixel counts
    const XorCounts c = evaluate(model, pose, INT64_MAX);
    r.pose = pose;
    r.estimated = true;
    r.vertebrae = pose_vertebrae(model, spine, pose);
    r.fit.cost = c.cost();
    r.fit.xor_frontal_px = c.xor_px[0];
    r.fit.xor_lateral_px = c.xor_px[1];
    r.fit.silhouette_frontal_px = c.silhouette_px[0];
    r.fit.silhouette_lateral_px = c.silhouette_px[1];
    r.fit.candidates = candidates + 1;
    if (!flag.empty()) r.fit.flag = std::string(flag);
    if (state == TrackingState::Tracking && c.cost_against(built_silhouette_px) > opt.lost_cost)
      state = TrackingState::Lost;
    r.state = state;
    r.neck = r.vertebrae[kNeckIndex].body_center;
    r.waist = r.vertebrae[kWaistIndex].body_center;
    r.neck_dir = r.vertebrae[kNeckIndex].q * Eigen::Vector3d::UnitY();
    r.waist_dir = r.vertebrae[kWaistIndex].q * Eigen::Vector3d::UnitY();
    return r;
  }

  // A pair of the model's building, fitted against the model built so far
  // (docs/cvsm.md, "Provisional model"): published as tracking when it
  // passes what a tracked pair must — a fit within lost_cost, the lower
  // body seen in a view, an axial twist whose sign the views tell (and
  // the fit's own, not its mirror) — and a fit no worse than the best of
  // the building's pairs by more than kProvisionalCostRise, with that rise
  // to spare below lost_cost (the cost goes on rising as the model
  // completes: side-on to the frontal camera the building's pairs fitted at
  // 0.34–0.347, 140–210 mm off, and the complete model was lost). The
  // caller has also waited for the facing side told and an uninterrupted
  // building (facing_settled, building_interrupted). Else it stays init.
  // The pose is not changed: the model goes on being built from it.
  // The rise: the building fits shape and pose together, so a posture the
  // model does not hold (a lunge, a raised arm) is partly taken into the
  // shape and the pose follows it less; the cost says so before the
  // posture goes wrong. On the development subject's lunge the fit was
  // 46 mm off at a rise of 0.048 and 51 mm at 0.067, while reaching arms
  // rose to 0.039 at 20 mm (docs/cvsm.md, "Provisional model").
  static constexpr double kProvisionalCostRise = 0.04;
  double best_building_cost = 2;  // the lowest reported cost of the building's pairs
  // Both views' silhouette pixels on the pair that completed the model: what
  // a tracked pair's misfit is weighed against where its own outline is
  // smaller (XorCounts::cost_against). 0 while the model is being built.
  std::int64_t built_silhouette_px = 0;
  void publish_provisional(CvsmResult& r) {
    if (r.fit.cost > opt.lost_cost - kProvisionalCostRise || r.fit.cost > best_building_cost + kProvisionalCostRise) return;
    if (hiding[0] && hiding[1]) return;
    const CvsmPose built = pose;
    cost->set_row_step(opt.search_row_step);  // the twist margin's rows
    int candidates = 0;
    const TwistCheck twist = check_twist_sign(candidates);
    cost->set_row_step(1);
    const bool mirrored = pose.twist != built.twist;
    pose = built;
    r.fit.candidates = r.fit.candidates.value_or(0) + candidates;
    if (twist.checked) r.twist_sign_margin_px = twist.margin_px;
    if (!twist.resolved() || mirrored) return;
    r.state = TrackingState::Tracking;
    r.provisional = true;
  }

  CvsmResult no_person(std::string_view flag) {
    CvsmResult r;
    r.state = TrackingState::Lost;
    r.fit.cost = 1.0;
    r.fit.candidates = 0;
    r.fit.flag = std::string(flag);
    if (phase == Phase::Building && subject) building_interrupted = true;
    if (phase != Phase::Building) phase = Phase::Searching;
    if (phase != Phase::Building && flag == "no_person") left_view = true;
    return r;
  }

  // The subject model from the first clean pair: measured, then standing or
  // seated chosen. Returns the cost evaluations spent.
  int start_subject(const BitMask& frontal, const BitMask& lateral, const CvsmOptions& options) {
    subject = cvsm_detail::initial_subject(rig, spec, spine, options, frontal, lateral);
    subject->measured_spine = options.spine_placement == SpinePlacementMode::Measured;
    subject->lower_body_hidden = hiding[0] || hiding[1];
    facing_guard = {};
    held_away = false;
    built_silhouette_px = 0;
    building_interrupted = false;
    if (opt.heading == HeadingRange::Fixed) return cvsm_detail::choose_posture(*subject, *cost, spec, spine, options);
    // The heading is chosen on the posture the first pair's estimate starts
    // from (standing). A seated adult facing the frontal camera drew better
    // as a standing one turned 30° than facing it (ANSUR 27006, seated
    // flexion: every vertebra 21.6 → 41.2 mm), and his shape was then built
    // turned. So once the posture chosen differs, the heading is chosen
    // again on it, and the posture again if the heading moved.
    const SubjectPosture probed_on = subject->shape.posture;
    cvsm_detail::HeadingChoice heading = cvsm_detail::choose_heading(*subject, *cost, spec, spine, options);
    int evaluations = heading.evaluations + cvsm_detail::choose_posture(*subject, *cost, spec, spine, options);
    if (subject->shape.posture != probed_on) {
      const double chosen = subject->pose.heading;
      heading = cvsm_detail::choose_heading(*subject, *cost, spec, spine, options);
      evaluations += heading.evaluations;
      if (subject->pose.heading != chosen) evaluations += cvsm_detail::choose_posture(*subject, *cost, spec, spine, options);
    }
    heading_resolved = heading.resolved();
    front_back = {};
    if (heading.sides_compared) {
      front_back.add(heading);
      heading_resolved = front_back.decided();
    }
    return evaluations;
  }

  // Where the range does not take the side turned away (fixed, front):
  // `s` at its heading against its mirror, added to the guard's evidence;
  // once it says the subject faces away, the subject model is turned to
  // that side (fitted as he stands) and held there, every posture lost
  // (docs/cvsm.md, "Turned away from the range"). Returns evaluations.
  // On the pair that completes the model (`completes`) a lean away is enough.
  int weigh_facing(cvsm_detail::SubjectEstimate& s, bool completes) {
    if (opt.heading == HeadingRange::Any || !facing_guard.weighing()) return 0;
    const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(s, *cost, spec, spine);
    facing_guard.add(choice);
    if (facing_guard.says_away() || (completes && facing_guard.leans_away())) {
      held_away = true;
      s.pose = cvsm_detail::turned_in_place(cvsm_detail::build(s, spec, spine), spine, s.pose, choice.away_heading);
    }
    return choice.evaluations;
  }
  // The options a pair's own first estimate is placed with: the subject
  // model's — without a given stature the views contradicted (weighed for
  // a man 250 mm shorter than in view, he led for his mirror and every pair
  // was held turned away).
  CvsmOptions placing_options() const { return subject->rejected_stature_mm ? without_given_body(opt) : opt; }
  // This pair's own first estimate at the heading the range allows nearest
  // the subject's (its mirror when he is held turned away), shaped as the
  // subject model so far: weighed from here, the side the model was refined
  // at does not start ahead.
  cvsm_detail::SubjectEstimate fresh_at_allowed_heading(const BitMask& frontal, const BitMask& lateral,
                                                        double heading_deg) const {
    cvsm_detail::SubjectEstimate fresh =
        cvsm_detail::initial_subject(rig, spec, spine, placing_options(), frontal, lateral);
    fresh.measured_spine = subject->measured_spine;
    fresh.shape.posture = subject->shape.posture;
    const double allowed = cvsm_detail::heading_allowed(opt.heading, heading_deg)
                               ? heading_deg
                               : cvsm_detail::wrapped_heading(heading_deg + 180);
    if (allowed != fresh.pose.heading)
      fresh.pose = cvsm_detail::turned_in_place(cvsm_detail::build(fresh, spec, spine), spine, fresh.pose, allowed);
    return fresh;
  }
  // Found again after he left the view (he may come back turned round):
  // the sides weighed on this pair alone, the mirror believed when it leads
  // by kAwayPreferenceFraction. Then held turned away as after the model.
  // Not after a fit merely lost in view: on cameras tilted 45° one pair's
  // lead strays past the margin, and 28496 tracked 22 % instead of 58 %.
  void weigh_reacquired(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
    facing_guard.restart();
    const cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, pose.heading);
    const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(fresh, *cost, spec, spine);
    r.fit.candidates = r.fit.candidates.value_or(0) + choice.evaluations;
    facing_guard.add(choice);
    if (!facing_guard.says_away()) return;
    held_away = true;
    pose = cvsm_detail::turned_in_place(model, spine, pose, choice.away_heading);
    facing_guard.restart();
  }
  // A pair tracked while the subject is held turned away: lost, flagged.
  // Every kRecheckPairs the sides are weighed again on this pair (he may
  // have turned round); once the allowed side leads, the pose is turned
  // back to it and the next pair is tracked as usual.
  void hold_turned_away(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
    if (facing_guard.recheck_due()) {
      cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, pose.heading);
      const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(fresh, *cost, spec, spine);
      r.fit.candidates = r.fit.candidates.value_or(0) + choice.evaluations;
      facing_guard.add(choice);
      if (facing_guard.says_back()) {
        held_away = false;
        pose = cvsm_detail::turned_in_place(model, spine, pose, choice.facing_heading);
        facing_guard.restart();
      } else if (facing_guard.leans_away()) {
        facing_guard.restart();  // still turned away: the next weighing starts afresh
      }
    }
    if (r.state == TrackingState::Tracking) {
      r.state = TrackingState::Lost;
      // Turned away says more than an unresolved twist (of a mirror image).
      if (!r.fit.flag || *r.fit.flag == kTwistUnresolvedFlag) r.fit.flag = std::string(kFacingAwayFlag);
    }
  }

  CvsmResult track(const BitMask& frontal, const BitMask& lateral, std::string_view flag) {
    if (frontal.empty() || lateral.empty() || frontal.width() != lateral.width() || frontal.height() != lateral.height())
      return no_person("no_person");
    if (frontal.count() < opt.min_silhouette_px || lateral.count() < opt.min_silhouette_px) return no_person("no_person");
    if (!cost || cost_width != frontal.width() || cost_height != frontal.height()) {
      cost = std::make_unique<XorCost>(rig, frontal.width(), frontal.height());
      cost_width = frontal.width();
      cost_height = frontal.height();
    }
    cost->set_silhouettes(frontal, lateral);
    silhouette_px = frontal.count() + lateral.count();
    find_hidden(frontal, lateral);

    if (phase == Phase::Building) {
      // Building the subject model: only from clean frames.
      if (!flag.empty()) return no_person(flag);
      int candidates = 0;
      if (!subject) {
        candidates += start_subject(frontal, lateral, opt);
        if (cvsm_detail::check_given_stature(*subject)) {
          // Someone else's stature: the model so far was placed and shaped
          // for it (fitted 12.2 mm off where nothing given gave 9.5), so it
          // starts over as if nothing were given.
          const std::optional<double> rejected = subject->rejected_stature_mm;
          candidates += start_subject(frontal, lateral, without_given_body(opt));
          subject->rejected_stature_mm = rejected;
        }
      } else if (!heading_resolved) {
        // The first pairs did not tell front from back: the full circle
        // again on this one (the subject may have bent or turned since),
        // from this pair's own first estimate as on the first pair. (From
        // the model refined so far, the heading it was refined at starts
        // ahead of the others and wins by that alone.)
        cvsm_detail::SubjectEstimate fresh =
            cvsm_detail::initial_subject(rig, spec, spine, placing_options(), frontal, lateral);
        fresh.measured_spine = subject->measured_spine;
        fresh.shape.posture = subject->shape.posture;
        const cvsm_detail::HeadingChoice heading = cvsm_detail::choose_heading(fresh, *cost, spec, spine, opt);
        heading_resolved = heading.resolved();
        candidates += heading.evaluations;
        if (heading.sides_compared) {
          // Over the full circle: decided by the comparisons summed so far.
          front_back.add(heading);
          heading_resolved = front_back.decided();
          fresh.pose.heading = front_back.heading(heading);
        }
        if (heading_resolved && fresh.pose.heading != subject->pose.heading)
          subject->pose = cvsm_detail::turned_in_place(model, spine, subject->pose, fresh.pose.heading);
      }
      if (facing_guard.weighing() && opt.heading != HeadingRange::Any) {
        cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, subject->pose.heading);
        candidates += weigh_facing(fresh, init_frames + 1 >= opt.subject_frames);
        if (held_away)
          subject->pose = cvsm_detail::turned_in_place(cvsm_detail::build(*subject, spec, spine), spine, subject->pose,
                                                       fresh.pose.heading);
      }
      candidates += cvsm_detail::refine_subject(*subject, *cost, spec, spine);
      model = cvsm_detail::build(*subject, spec, spine);
      search_model = thin_trunk(model, opt.search_vertebra_step);
      armless_model = without_arms(search_model);
      pose = subject->pose;
      home = pose.translation;
      standing_height.reset();
      ++init_frames;
      CvsmResult r = finish(TrackingState::Init, candidates, flag);
      best_building_cost = std::min(best_building_cost, r.fit.cost);
      // The model is complete only once the heading is known: a subject
      // whose front the views cannot tell from its back stays init.
      if (init_frames >= opt.subject_frames && heading_resolved) {
        built_silhouette_px = *r.fit.silhouette_frontal_px + *r.fit.silhouette_lateral_px;
        r.state = r.fit.cost > opt.lost_cost ? TrackingState::Lost : TrackingState::Tracking;
        phase = r.state == TrackingState::Lost ? Phase::Searching : Phase::Tracking;
        withhold_unseen_pelvis(frontal, lateral, r);
        if (held_away) hold_turned_away(frontal, lateral, r);
        withhold_unexplained_legs(frontal, lateral, r);
      } else if (init_frames >= opt.provisional_frames && heading_resolved && !held_away && facing_settled() &&
                 !building_interrupted && pelvis_seen(frontal, lateral, r)) {
        publish_provisional(r);
      }
      return r;
    }

    const CvsmPose before = pose;
    int candidates = 0;
    // Candidates are compared on every other row: half the scan conversion
    // and counting, and a person is well over a hundred rows tall.
    cost->set_row_step(opt.search_row_step);
    // Whether the search started from a predicted motion (it keeps its
    // result even when lost; otherwise the last good pose is kept).
    const bool predicted = phase == Phase::Predicting;
    const bool searched_globally = phase == Phase::Searching;
    // Auto limbs: the fixed fit first, whatever the arms did before.
    if (opt.limbs == LimbMode::Auto) pose.limbs = {};
    if (searched_globally) {
      anchored = false;
      candidates = probe_headings();
      candidates += global_search(opt.global_budget);
      // The limbs from wherever they were, in wide steps, then the trunk
      // again with them.
      candidates += limb_search(2 * opt.limb_budget, 8, 3);
      candidates += joint_refinement(opt.joint_budget);
      anchored = true;
    } else {
      // Hierarchical: the trunk with the limbs held, the limbs with the
      // trunk held, the trunk once more.
      if (opt.limbs == LimbMode::Articulated) trunk_search_model = &armless_model;
      // Cut to its coarse steps only where the refinement surely follows
      // (fixed limbs); with auto it may not (refine_follows()).
      candidates = local_search(refining() && opt.limbs == LimbMode::Fixed ? opt.refined_local_budget : opt.local_budget);
      candidates += follow_heading(searched_cost);
      candidates += follow_step();
      trunk_search_model = &search_model;
      candidates += limb_search(opt.limb_budget, 4, 2);
      candidates += joint_refinement(opt.joint_budget);
    }
    TwistCheck twist = check_twist_sign(candidates);
    // Refined as it was searched: after a global search, unanchored (the
    // subject may have stepped; the anchor follows below).
    CvsmResult r = settle(frontal, lateral, candidates, flag, searched_globally);
    if (opt.limbs == LimbMode::Auto) try_arms(r, twist, before, searched_globally, flag, frontal, lateral);
    if (twist.checked) r.twist_sign_margin_px = twist.margin_px;
    // A silhouette flag says more about the pair; it stays.
    if (r.state == TrackingState::Tracking && !twist.resolved() && !r.fit.flag) r.fit.flag = std::string(kTwistUnresolvedFlag);
    // Found again, but its front not told from its back: not published.
    if (searched_globally && !heading_resolved) r.state = TrackingState::Lost;
    if (r.state == TrackingState::Lost) {
      // Keep the last good pose as the start of the next search.
      if (!predicted) pose = before;
      phase = Phase::Searching;
    } else {
      if ((pose.translation - home).norm() > kNewHomeMm) home = pose.translation;
      previous = before;
      phase = flag.empty() ? Phase::Predicting : Phase::Tracking;
    }
    // An occluder hides the lower body in both views: no view sees the
    // legs or the pelvis's lower outline, so the waist rests on the model's
    // guess of them (docs/cvsm.md, "Occluded lower body"). Not published
    // as tracking; the fit goes on from this pose.
    if (r.state == TrackingState::Tracking && hiding[0] && hiding[1]) {
      r.state = TrackingState::Lost;
      if (!r.fit.flag) r.fit.flag = std::string(kLowerBodyHiddenFlag);
    }
    withhold_unseen_pelvis(frontal, lateral, r);
    withhold_bent_knees(r);
    if (searched_globally && r.state == TrackingState::Tracking && left_view && !held_away &&
        opt.heading != HeadingRange::Any)
      weigh_reacquired(frontal, lateral, r);
    if (r.state == TrackingState::Tracking) left_view = false;
    if (held_away) hold_turned_away(frontal, lateral, r);
    // After the heading's checks: turned away says more (a mirror image).
    withhold_unexplained_legs(frontal, lateral, r);
    return r;
  }

  // The pelvis well below where the subject stood on the first upright
  // pair tracked on the complete model (docs/cvsm.md, "A step aside"): the
  // knees are bent (a lunge, a squat), which the fixed limbs' straight legs
  // cannot draw, so the waist's height rests on the trunk's outline alone
  // and was 45–70 mm off on the development subject's lunge. Not published
  // as tracking. With both knees bent by θ (thigh and shank ≈ 0.25 of the
  // stature each, each turned θ/2 from the vertical) the hips drop
  // 2·0.25·H·(1 − cos θ/2): 25 mm is about 30° for a 1.7 m subject;
  // standing, the anchor lets the hips sway by at most 15 mm on the
  // phantom's rows. Measured by the tracked fit itself, not by the model's
  // building, which fits shape and pose together: a model held to a given
  // stature 250 mm above the body's sits 120 mm lower once tracked, its
  // knees straight. Only with the trunk upright, as the step search: bent
  // forward in a view that looks down, the fit lowers the hips too (a
  // camera tilted 45°: 6 of 30 pairs of a bend lost without it).
  static constexpr double kKneesBentMm = 25;
  std::optional<double> standing_height;  // reset when a subject model is built
  void withhold_bent_knees(CvsmResult& r) {
    if (r.state != TrackingState::Tracking || opt.limbs == LimbMode::Articulated ||
        model.shape.posture != SubjectPosture::Standing || std::abs(to_params(pose)[0]) > kStepUprightDeg)
      return;
    if (!standing_height) standing_height = pose.translation.y();
    if (pose.translation.y() > *standing_height - kKneesBentMm) return;
    r.state = TrackingState::Lost;
    if (!r.fit.flag) r.fit.flag = std::string(kKneesBentFlag);
  }

  // Legs the held-straight model cannot draw, under a trunk leaning over
  // them and a fit worse than the subject's baseline (legs_unexplained.hpp,
  // docs/cvsm.md, "Legs the fit leaves out"): a step or a lunge read as a
  // side bend. Not published as tracking; as with bent knees, the fit goes
  // on from this pose (the phase is kept: a search from scratch would not
  // draw the legs either).
  void withhold_unexplained_legs(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
    if (r.state != TrackingState::Tracking || opt.limbs == LimbMode::Articulated ||
        model.shape.posture != SubjectPosture::Standing)
      return;
    const PoseParams a = to_params(r.pose);
    cvsm_detail::LegsEvidence e;
    e.lean_deg = std::abs(a[1] + a[4]);
    e.cost_rise = r.fit.cost - best_building_cost;
    // The cheap bounds first: the legs' share renders both views.
    if (e.lean_deg < cvsm_detail::kLegsLeanDeg || e.cost_rise <= cvsm_detail::kLegsCostRise) return;
    // The reported pose's points (the heading's checks evaluate others).
    control_points(model, r.vertebrae, points, r.pose.limbs, r.pose.heading);
    e.outside_share = residual_below_waist(frontal, lateral, r, BelowWaist::SilhouetteOutside);
    if (!cvsm_detail::legs_unexplained(e)) return;
    r.state = TrackingState::Lost;
    // A silhouette flag says more about the pair and stays; twist_unresolved
    // qualifies a tracked posture only, and would not say why this one is lost.
    if (!r.fit.flag || *r.fit.flag == kTwistUnresolvedFlag) r.fit.flag = std::string(kLegsUnexplainedFlag);
  }

  // Neither view shows the pelvis — each ends before it (an edge of the
  // image, docs/cvsm.md, "Pelvis out of the picture") or an occluder hides
  // it: the waist rests on the model's proportions, not on the views. Not
  // published as tracking, as with the occluder alone above.
  void withhold_unseen_pelvis(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) const {
    if (r.state != TrackingState::Tracking || pelvis_seen(frontal, lateral, r)) return;
    r.state = TrackingState::Lost;
    if (!r.fit.flag) r.fit.flag = std::string(kLowerBodyHiddenFlag);
  }

  // Whether one view at least shows the pelvis (neither an occluder nor the
  // image's edge hides it there): a provisional posture needs it too.
  bool pelvis_seen(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r) const {
    if (!hiding[0] && !cvsm_detail::pelvis_out_of_view(rig.frontal, frontal, model, r.vertebrae)) return true;
    return !hiding[1] && !cvsm_detail::pelvis_out_of_view(rig.lateral, lateral, model, r.vertebrae);
  }

  int cost_width = 0, cost_height = 0;
  // Whether the views told the subject's front from its back when the
  // heading was last searched (choose_heading while building,
  // probe_headings at reacquisition): until they do, nothing is
  // published as tracking (docs/cvsm.md, "Heading").
  bool heading_resolved = true;
  cvsm_detail::FrontBackEvidence front_back;  // the building pairs' mirror comparisons
  // Where the range does not take the side turned away: the evidence of the
  // side he faces, and whether he is held turned away (nothing tracking).
  cvsm_detail::FacingGuard facing_guard;
  bool held_away = false;
  // A pair was left out of the building (occluded, no one in view) since
  // its first: the model is built from the pairs between, and no early
  // posture is published on it (in a cluttered room, 11953's were 50–56 mm
  // off where the complete model's were as well; docs/cvsm.md, "Provisional
  // model").
  bool building_interrupted = false;
  // Whether an early posture may be published as to the side faced: the
  // facing check has decided for the allowed side (over the full circle,
  // heading_resolved says it). Undecided, the model may be its own mirror
  // or barely fit (carrying a box, 25762's side led by under 1 %).
  bool facing_settled() const { return opt.heading == HeadingRange::Any || facing_guard.says_allowed(); }
  bool left_view = false;  // no person in view since the last tracked pair

  // What an occluder in front of the person hides in each view (docs/cvsm.md,
  // "Occluded lower body"): the cost does not count the model there.
  std::array<BitMask, 2> hidden;
  std::array<bool, 2> hiding{};
  void find_hidden(const BitMask& frontal, const BitMask& lateral) {
    // The floor under the person: under the waist once a model exists,
    // else under the point the station looks at.
    Eigen::Vector3d under = Eigen::Vector3d::Zero();
    if (init_frames > 0) {
      const Eigen::Vector3d waist = pose_vertebrae(model, spine, pose)[kWaistIndex].body_center;
      under = {waist.x(), 0, waist.z()};
    }
    const BitMask* masks[2] = {&frontal, &lateral};
    const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
    for (std::size_t v = 0; v < 2; ++v) {
      hiding[v] = false;
      const std::optional<Eigen::Vector2d> floor = cams[v]->project(under);
      if (!floor) continue;
      if (const auto edge = cvsm_detail::find_occluder_edge(*masks[v], floor->y())) {
        cvsm_detail::hidden_below(*edge, *masks[v], hidden[v]);
        hiding[v] = true;
      }
    }
    cost->set_hidden(hiding[0] ? &hidden[0] : nullptr, hiding[1] ? &hidden[1] : nullptr);
  }
};

CvsmTracker::CvsmTracker(const CameraRig& rig, CvsmOptions options) : impl_(std::make_unique<Impl>(rig, std::move(options))) {}
CvsmTracker::~CvsmTracker() = default;
CvsmTracker::CvsmTracker(CvsmTracker&&) noexcept = default;
CvsmTracker& CvsmTracker::operator=(CvsmTracker&&) noexcept = default;

CvsmResult CvsmTracker::track(const BitMask& frontal, const BitMask& lateral) {
  return impl_->track(frontal, lateral, {});
}

CvsmResult CvsmTracker::track(const SilhouetteResult& frontal, const SilhouetteResult& lateral) {
  for (const SilhouetteResult* s : {&frontal, &lateral})
    if (s->status == SilhouetteStatus::LearningBackground || s->status == SilhouetteStatus::NoBackground ||
        s->status == SilhouetteStatus::NoPerson) {
      CvsmResult r = impl_->no_person(to_string(s->status));
      // No background yet: not lost, still starting up (docs/interfaces.md §3, init).
      if (s->status != SilhouetteStatus::NoPerson) r.state = TrackingState::Init;
      return r;
    }
  std::string_view flag = flag_of(frontal.status);
  if (flag.empty()) flag = flag_of(lateral.status);
  return impl_->track(frontal.mask, lateral.mask, flag);
}

BitMask CvsmTracker::fitted_mask(View view) {
  Impl& m = *impl_;
  // After finish(), `points` hold the full model at the reported pose and
  // the cost counts every row.
  if (!m.cost || (m.phase != Phase::Tracking && m.phase != Phase::Predicting)) return {};
  return m.cost->render(m.model, m.points, view);
}

const BodyModel* CvsmTracker::subject_model() const { return impl_->init_frames > 0 ? &impl_->model : nullptr; }

std::optional<double> CvsmTracker::rejected_stature_mm() const {
  return impl_->subject ? impl_->subject->rejected_stature_mm : std::nullopt;
}

void CvsmTracker::reset() {
  CameraRig rig = impl_->rig;
  CvsmOptions opt = impl_->opt;
  impl_ = std::make_unique<Impl>(rig, std::move(opt));
}

}  // namespace spinewatch
