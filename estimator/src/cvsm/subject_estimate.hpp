#pragma once
// The subject-specific model (the paper's future work (2)): height, trunk
// widths and depths and the subject's place, measured from the first
// upright silhouettes and refined by the same XOR fit.
#include "cvsm/xor_cost.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"

namespace spinewatch::cvsm_detail {

struct SubjectEstimate {
  BodyShape shape;
  Eigen::Vector3d base_l5{0, 0, 0};  // standing: y follows the height
  double crown_y = 0;                // top of the head (mm, world): fixes shape.head_scale
  // The spine sits where it does in measured people of the subject's
  // stature (spine_placement.hpp), not at fixed fractions of the model's
  // height: the height the outline fit settles on follows the person's
  // proportions (±40 mm from the stature on ANSUR bodies), and the fitted
  // crown trades against the head's shape; the stature is what the top
  // of the head measured in the first frame (standing).
  bool measured_spine = false;
  double measured_crown_mm = 0;  // the silhouettes' top in the first frame; 0 when cut off
  // Given for this worker: the stature, standing or seated, and (with the
  // generic placement) the model's height, neither then searched.
  std::optional<double> given_stature_mm;
  // Given skin landmarks (C7, iliac crest): they place T1 and L5 instead of
  // the stature regressions; set aside with a rejected stature.
  std::optional<double> given_c7_mm, given_crest_mm;
  // Given mass: with the stature, the BMI the spine's depth is placed for;
  // without it, the BMI the fitted waist depth implies.
  std::optional<double> given_mass_kg;
  // A given stature the standing silhouettes contradicted (see
  // check_given_stature): set aside, and the stature measured instead.
  std::optional<double> rejected_stature_mm;
  // An occluder hides the lower body in a view (cvsm/occluder_edge.hpp):
  // the standing and seated models are told apart by what remains, so the
  // seated one is compared at its best height, not at three guesses.
  bool lower_body_hidden = false;
  CvsmPose pose;
  // Seated, the crown is measured on the first pair, whose trunk may be
  // bent forward or sideways: the crown it would have upright lies higher
  // by what that pose lowers the model's head (crown_lift), and the spine
  // hangs from there. Set from the first pair's pose once its posture and
  // heading are chosen (CvsmTracker's start_subject), then held: a later
  // pair's pose is not the one the crown was measured in. Unset (the first
  // pair's own search), the spine hangs from the crown as measured.
  std::optional<double> crown_lift_mm;
};

// Direct measurements: height from the top of the head in both views, the
// trunk's centre line from the middle rows, the spine behind it by the
// generic fraction of the trunk depth.
SubjectEstimate initial_subject(const CameraRig& rig, const CvsmSpec& spec, const SpineSpec& spine,
                                const CvsmOptions& options, const BitMask& frontal, const BitMask& lateral);
// Standing or seated: as configured, or whichever fits the silhouettes
// better. Returns the cost evaluations spent.
int choose_posture(SubjectEstimate& subject, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                   const CvsmOptions& options);
// Standing, with the top of the head in view, a given stature more than
// kStatureMismatchMm (anatomy/worker.hpp) below it is someone else's: it
// is set aside (rejected_stature_mm) and the height measured and searched
// as when nothing is given. True when it was. A body that looks shorter
// than the given stature may be bending: that one stands, as it does
// seated, where the crown does not measure the stature.
bool check_given_stature(SubjectEstimate& subject);
// The options without the worker's given body (stature, landmarks, mass):
// for a subject whose given stature the views contradicted.
CvsmOptions without_given_body(CvsmOptions o);
// What a round of the shape fit may move: everything, or all but the
// height (held as built so far).
enum class ShapeRefinement { Full, HeightHeld };
// One round of the shape fit on the current silhouettes; returns evaluations.
int refine_subject(SubjectEstimate& subject, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                   int budget = 160, ShapeRefinement what = ShapeRefinement::Full);
// Standing with the measured placement and the crown in neither view, the
// model's height is the stature the spine is placed for: nothing else
// measures it.
bool stature_is_height(const SubjectEstimate& subject);
BodyModel build(const SubjectEstimate& subject, const CvsmSpec& spec, const SpineSpec& spine);
// The lift of SubjectEstimate::crown_lift_mm for the estimate's pose (its
// held value once set); 0 where the spine does not hang from a measured
// crown (standing, the generic placement, the crown cut off).
double crown_lift(const SubjectEstimate& subject, const CvsmSpec& spec, const SpineSpec& spine);
// A smaller lift is not applied: under half a pixel row of the crown's
// measurement (7–8 mm a row for a seated adult filling 170 of the 240 rows),
// it is below what the crown is measured to, and it would only move where
// the shape fit's descent ends (a 0.1 mm lift moved seated rows by ±1 mm).
inline constexpr double kMinCrownLiftMm = 3.0;
// The estimate's XOR cost against the current silhouettes (`points` is
// scratch).
std::int64_t subject_cost(const SubjectEstimate& subject, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                          std::vector<Eigen::Vector3d>& points, std::int64_t limit);

}  // namespace spinewatch::cvsm_detail
