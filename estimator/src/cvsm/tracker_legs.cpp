// What the held-straight legs ("fixed" limbs, and "auto"'s fixed fit)
// cannot draw (tracker_impl.hpp): a step aside, searched again with the
// legs not counted; bent knees and legs the fit leaves out, withheld from
// tracking (docs/cvsm.md, "A step aside", "Legs the fit leaves out").
#include <algorithm>
#include <cmath>

#include "cvsm/legs_region.hpp"
#include "cvsm/legs_unexplained.hpp"
#include "cvsm/lower_residual.hpp"
#include "cvsm/tracker_impl.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {
namespace {

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
constexpr double kStepMinMm = 20;
constexpr double kStepMarginFraction = cvsm_detail::kHeadingMarginFraction;
// Only where the local search bent the trunk sideways: a step drawn by
// closed legs comes out as a side bend over hips that stayed (stride,
// 28496: 39°), and a twisting or swaying subject was otherwise moved by
// it (the exposure shift's twists: 7.87 s over 60° read as 6.07 s).
constexpr double kStepSideBendDeg = 8;

}  // namespace

int CvsmTracker::Impl::follow_step() {
  const PoseParams a = to_params(pose);
  if (opt.limbs == LimbMode::Articulated || std::abs(a[0]) > kStepUprightDeg || std::abs(a[1]) < kStepSideBendDeg)
    return 0;
  const SpinePose v = pose_vertebrae(model, spine, pose);
  cvsm_detail::hide_below_hips(rig.frontal, model, v, hidden_in(0), cost_width, cost_height, legs_hidden[0]);
  cvsm_detail::hide_below_hips(rig.lateral, model, v, hidden_in(1), cost_width, cost_height, legs_hidden[1]);
  cost->set_hidden(&legs_hidden[0], &legs_hidden[1]);
  anchored = false;
  auto trunk_cost = [&](const PoseParams& q, std::int64_t limit) { return cost_of(q, limit); };
  const std::int64_t searched = cost_of(a, INT64_MAX);
  PoseParams straight = a;
  straight[1] = straight[4] = 0;  // no side bend or pelvis tilt; the twist kept (a twist is not a step)
  const auto moved = coordinate_descent(straight, cost_of(straight, INT64_MAX), PoseParams{0, 0, 0, 0, 0, 40, 0, 40}, 3, 24, trunk_cost);
  const auto settled = coordinate_descent(moved.params, moved.best, PoseParams{4, 4, 4, 4, 2, 10, 6, 10}, 3, 60, trunk_cost);
  anchored = true;
  cost->set_hidden(hidden_in(0), hidden_in(1));
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

double CvsmTracker::Impl::residual_below_waist(const BitMask& frontal, const BitMask& lateral, const CvsmResult& r,
                                               BelowWaist what) {
  const BitMask* masks[2] = {&frontal, &lateral};
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  std::int64_t n = 0;
  for (std::size_t v = 0; v < 2; ++v) {
    const std::optional<Eigen::Vector2d> waist = cams[v]->project(r.waist);
    if (!waist) continue;
    const BitMask drawn = cost->render(model, points, v == 0 ? View::Frontal : View::Lateral);
    const BitMask* h = hidden_in(v);
    const int row = static_cast<int>(std::ceil(waist->y()));
    n += what == BelowWaist::SilhouetteOutside ? cvsm_detail::silhouette_outside_below(drawn, *masks[v], h, row)
                                               : cvsm_detail::xor_below(drawn, *masks[v], h, row);
  }
  return static_cast<double>(n) / static_cast<double>(std::max<std::int64_t>(1, silhouette_px));
}

namespace {

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
constexpr double kKneesBentMm = 25;

}  // namespace

void CvsmTracker::Impl::withhold_bent_knees(CvsmResult& r) {
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
void CvsmTracker::Impl::withhold_unexplained_legs(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
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

}  // namespace spinewatch
