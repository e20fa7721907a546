#pragma once
// Legs the held-straight model cannot draw (docs/cvsm.md, "Legs the fit
// leaves out"). With the legs held straight and closed ("fixed", and the
// fixed fit of "auto"), a step or a lunge puts a leg where the model has
// none; the fit then bends the trunk over the leg that stood still, or
// tilts the pelvis, to reach the shoulders, and the cost rises. When all
// three show on one pair the posture rests on legs the views contradict,
// and it is not published as tracking.

namespace spinewatch::cvsm_detail {

// What a tracked pair's fit says about its legs.
struct LegsEvidence {
  // Share of both silhouettes' pixels below the waist that the fitted model
  // does not draw (silhouette_outside_below, over the silhouettes' pixels).
  double outside_share = 0;
  // How far the thorax leans sideways over the hips, degrees: the side bend
  // plus the pelvis's sideways tilt (both turn the thorax the same way for
  // the same sign), in magnitude. A pelvis tilted one way under a spine bent
  // back the other leaves the shoulders over the hips (a step followed,
  // stride on 28496: −8° and +9°) and is not a lean.
  double lean_deg = 0;
  // The fit's cost above the subject's own baseline (the best of the model's
  // building pairs), in shares of the silhouettes' pixels.
  double cost_rise = 0;
};

// Each bound is one the fit already uses for the same question, not one fitted
// to the phantom's table:
// - the arms' pass refuses a result leaving more than this share unexplained
//   below the waist (tracker_limbs.cpp, kArmsLowerResidualMax): above it the legs
//   moved;
inline constexpr double kLegsOutsideShare = 0.06;
// - the step search runs on a side bend of this much (kStepSideBendDeg): a step
//   drawn by closed legs comes out as a side bend;
inline constexpr double kLegsLeanDeg = 8;
// - the arms are searched where the cost rose this much over the baseline
//   (kArmsEvidenceRise): the fit no longer explains the subject as it did.
inline constexpr double kLegsCostRise = 0.1;

inline bool legs_unexplained(const LegsEvidence& e) {
  return e.outside_share > kLegsOutsideShare && e.lean_deg >= kLegsLeanDeg && e.cost_rise > kLegsCostRise;
}

}  // namespace spinewatch::cvsm_detail
