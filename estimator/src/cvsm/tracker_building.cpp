// The subject model's building (Phase::Building, tracker_impl.hpp): the
// first clean pairs measure and refine the subject's model, and from
// provisional_frames on its fit may be published early (docs/cvsm.md,
// "Provisional model").
#include <algorithm>
#include <optional>

#include "cvsm/tracker_impl.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {

CvsmResult CvsmTracker::Impl::building_pair(const BitMask& frontal, const BitMask& lateral, std::string_view flag) {
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
    subject->crown_lift_mm = cvsm_detail::crown_lift(*subject, spec, spine);
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
    // Held turned away, the heading found on the allowed side is his
    // reflection's (tracker_heading.cpp).
    if (heading_resolved && on_allowed_side(fresh.pose.heading) != subject->pose.heading)
      subject->pose = cvsm_detail::turned_in_place(model, spine, subject->pose, on_allowed_side(fresh.pose.heading));
  }
  weigh_seat_unseen();
  if (facing_guard.weighing() && opt.heading != HeadingRange::Any) {
    cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, subject->pose.heading);
    candidates += weigh_facing(fresh, init_frames + 1 >= opt.subject_frames);
    if (held_away)
      subject->pose = cvsm_detail::turned_in_place(cvsm_detail::build(*subject, spec, spine), spine, subject->pose,
                                                   fresh.pose.heading);
  }
  // Auto limbs: the arms found first, on the model built so far, and the
  // shape refined with them (subject_cost draws the pose's limbs): arms
  // raised while the model is built are then not taken into its height and
  // breadths.
  if (opt.limbs == LimbMode::Auto && init_frames > 0) building_arms(frontal, lateral, flag, candidates);
  candidates += cvsm_detail::refine_subject(*subject, *cost, spec, spine, 160, building_refinement());
  model = cvsm_detail::build(*subject, spec, spine);
  search_model = thin_trunk(model, opt.search_vertebra_step);
  armless_model = without_arms(search_model);
  pose = subject->pose;
  home = pose.translation;
  standing_height.reset();
  ++init_frames;
  CvsmResult r = finish(TrackingState::Init, candidates, flag);
  const double best_before = best_building_cost;
  best_building_cost = std::min(best_building_cost, r.fit.cost);
  // The model is complete only once the heading is known: a subject
  // whose front the views cannot tell from its back stays init.
  if (init_frames >= opt.subject_frames && heading_resolved) {
    built_silhouette_px = *r.fit.silhouette_frontal_px + *r.fit.silhouette_lateral_px;
    const bool moved_while_building = r.fit.cost > best_before + kBuildingCostRise;
    r.state = r.fit.cost > opt.lost_cost ? TrackingState::Lost : TrackingState::Tracking;
    phase = r.state == TrackingState::Lost ? Phase::Searching : Phase::Tracking;
    withhold_hidden_lower_body(r);
    withhold_unseen_pelvis(frontal, lateral, r);
    withhold_misplaced_head(frontal, lateral, r);
    if (held_away) hold_turned_away(frontal, lateral, r);
    withhold_unexplained_legs(frontal, lateral, r);
    if (moved_while_building) withhold_moved_while_building(r);
    unpublished_last = r.state != TrackingState::Tracking;
  } else if (init_frames >= opt.provisional_frames && heading_resolved && facing_settled() &&
             !building_interrupted && pelvis_seen(frontal, lateral, r) &&
             head_placed(frontal, lateral, r)) {
    publish_provisional(r);
  }
  return r;
}

// A building pair after the first gets the arms a tracked pair gets
// (try_arms), on the model built so far: where the fit with the arms
// hanging rises over the building's best by kBuildingCostRise — the rise
// at which the building starts taking a posture into the shape — or the
// arms were raised on the pair before. Where they explain the views, the
// subject's pose holds them and its shape is refined with them.
void CvsmTracker::Impl::building_arms(const BitMask& frontal, const BitMask& lateral, std::string_view flag,
                                      int& candidates) {
  model = cvsm_detail::build(*subject, spec, spine);
  search_model = thin_trunk(model, opt.search_vertebra_step);
  armless_model = without_arms(search_model);
  pose = subject->pose;
  const CvsmPose before = pose;
  pose.limbs = {};  // the fixed fit has the arms hanging, as on a tracked pair
  CvsmResult r = finish(TrackingState::Init, 0, flag);
  // The twist's sign is not judged on the building's pairs: try_arms'
  // check is not used here.
  TwistCheck unused;
  try_arms(r, unused, before, false, flag, frontal, lateral, ArmsPass::Building);
  candidates += r.fit.candidates.value_or(0);
  subject->pose = pose;
}

// A tall worker reaching forward while his model was built, his head
// above both pictures (ANSUR 28048, 1930 mm, a test-set adult of the
// varied phantom): refined on every pair, the height followed the reach
// from 1930 to 1974 mm as the building's cost rose from 0.09 to 0.18, and
// the spine placed for it; 30 of his 60 postures were more than 50 mm off
// (docs/cvsm.md, "Provisional model", *A height no crown measures*).
cvsm_detail::ShapeRefinement CvsmTracker::Impl::building_refinement() {
  if (init_frames == 0 || !cvsm_detail::stature_is_height(*subject)) return cvsm_detail::ShapeRefinement::Full;
  model = cvsm_detail::build(*subject, spec, spine);
  cost->set_row_step(1);
  const double built_cost = evaluate(model, subject->pose, INT64_MAX).cost();
  return built_cost > best_building_cost + kBuildingCostRise ? cvsm_detail::ShapeRefinement::HeightHeld
                                                             : cvsm_detail::ShapeRefinement::Full;
}

// The pair that completes the model fits worse than the building's best by
// more than a posture the model holds (kBuildingCostRise): the subject
// moved while it was built (arms raised, a lunge), the building took part
// of that posture into the shape, and the pose followed it less. Its
// posture is not published; the fit goes on from it, and the next pair
// that passes is held too (confirm_after_withheld). On the phantom
// baseline these completing pairs were 50–91 mm off (arms overhead, a
// lunge) and the pair after them 44–50 (docs/cvsm.md, "Provisional
// model").
void CvsmTracker::Impl::withhold_moved_while_building(CvsmResult& r) {
  if (r.state != TrackingState::Tracking) return;
  r.state = TrackingState::Lost;
  r.fit.flag = std::string(kMovedWhileBuildingFlag);
  withheld_last = true;
}

// The subject model from the first clean pair: measured, then standing or
// seated chosen. Returns the cost evaluations spent.
int CvsmTracker::Impl::start_subject(const BitMask& frontal, const BitMask& lateral, const CvsmOptions& options) {
  subject = cvsm_detail::initial_subject(rig, spec, spine, options, frontal, lateral);
  subject->measured_spine = options.spine_placement == SpinePlacementMode::Measured;
  subject->lower_body_hidden = hiding[0] || hiding[1];
  building_end_unseen = {};
  seat_unseen = {};
  facing_guard = {};
  held_away = false;
  away_followed = false;
  built_silhouette_px = 0;
  building_interrupted = false;
  if (opt.heading == HeadingRange::Fixed)
    return cvsm_detail::choose_posture(*subject, *cost, spec, spine, options) +
           cvsm_detail::seat_if_turned_away(*subject, *cost, spec, spine, options);
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
  // Out of the range's reach the side turned away is weighed on each
  // pair (weigh_facing); seated with his back to the camera, the standing
  // model is what would be weighed (facing_check.hpp).
  if (opt.heading != HeadingRange::Any) evaluations += cvsm_detail::seat_if_turned_away(*subject, *cost, spec, spine, options);
  heading_resolved = heading.resolved();
  front_back = {};
  if (heading.sides_compared) {
    front_back.add(heading);
    heading_resolved = front_back.decided();
  }
  return evaluations;
}

// A pair of the model's building, fitted against the model built so far
// (docs/cvsm.md, "Provisional model"): published as tracking when it
// passes what a tracked pair must — a fit within lost_cost, the lower
// body seen in a view, an axial twist whose sign the views tell (and
// the fit's own, not its mirror) — and a fit no worse than the best of
// the building's pairs by more than kBuildingCostRise, with that rise
// to spare below lost_cost (the cost goes on rising as the model
// completes: side-on to the frontal camera the building's pairs fitted at
// 0.34–0.347, 140–210 mm off, and the complete model was lost). The
// caller has also waited for the facing side told and an uninterrupted
// building (facing_settled, building_interrupted). Else it stays init.
// The pose is not changed: the model goes on being built from it.
void CvsmTracker::Impl::publish_provisional(CvsmResult& r) {
  if (r.fit.cost > opt.lost_cost - kBuildingCostRise || r.fit.cost > best_building_cost + kBuildingCostRise) return;
  if (lower_body_hidden_in_both()) return;
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

}  // namespace spinewatch
