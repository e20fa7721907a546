// The heading (tracker_impl.hpp; docs/cvsm.md, "Heading", "Turned away
// from the range"): followed pair by pair, probed over the range at
// (re)acquisition, and where the range does not take the side turned away,
// the side the subject faces weighed against its mirror.
#include <algorithm>
#include <vector>

#include "cvsm/tracker_impl.hpp"
#include "spinewatch/estimator/fit_flags.hpp"

namespace spinewatch {
namespace {

// follow_heading's step either way, degrees.
constexpr double kHeadingStepDeg = 2;

}  // namespace

// The heading per tracked pair: one step either way from where it was
// (a person turns a few degrees between pairs), kept when it fits
// better by more than four times the pair-to-pair noise of the cost
// (kHeadingMarginFraction): a few degrees of heading and of axial
// twist draw nearly the same outline, and the heading must not follow
// the twist. Two evaluations.
int CvsmTracker::Impl::follow_heading(std::int64_t current_cost) {
  if (opt.heading == HeadingRange::Fixed) return 0;
  const PoseParams a = to_params(pose);
  const auto gain = static_cast<std::int64_t>(cvsm_detail::kHeadingMarginFraction * static_cast<double>(silhouette_px) / cost->row_step());
  std::int64_t best = current_cost - gain;
  const double start = pose.heading;
  for (const double step : {kHeadingStepDeg, -kHeadingStepDeg}) {
    if (!cvsm_detail::heading_allowed(opt.heading, on_allowed_side(start + step))) continue;
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
  const double preferred =
      on_allowed_side(cvsm_detail::preferred_heading(opt.heading, on_allowed_side(pose.heading)));
  if (cvsm_detail::wrapped_heading(pose.heading) != preferred) {
    CvsmPose facing = pose;
    facing.heading = preferred;
    const std::int64_t facing_cost = cost_of(facing, a, INT64_MAX);
    const std::int64_t turned_cost = best < current_cost - gain ? best : current_cost;
    if (turned_cost >= cvsm_detail::cost_to_beat_facing(opt.heading, on_allowed_side(pose.heading), facing_cost,
                                                        static_cast<std::int64_t>(static_cast<double>(silhouette_px) / cost->row_step())))
      pose = facing;
    return 3;
  }
  return 2;
}

// Held turned away, the subject is followed on the side turned away: each
// heading is judged as its reflection (180° − h, the heading the frontal
// camera cannot tell from it), which the range allows.
double CvsmTracker::Impl::on_allowed_side(double heading_deg) const {
  return held_away ? cvsm_detail::wrapped_heading(180 - heading_deg) : heading_deg;
}

// At (re)acquisition the subject may have turned any way: the full
// circle, every kHeadingProbeDeg, at the upright trunk where the subject
// was last; the global search then starts from the best.
// Sets heading_resolved: whether the best heading beat every heading
// 90° or more from it by choose_heading's margin.
int CvsmTracker::Impl::probe_headings() {
  if (opt.heading == HeadingRange::Fixed) return 0;
  CvsmPose upright = pose;
  upright.flexion = upright.lateral = upright.twist = upright.pelvis_flexion = upright.pelvis_lateral = 0;
  struct Probe {
    CvsmPose pose;
    std::int64_t cost;
  };
  std::vector<Probe> probes;
  std::size_t best = 0;
  for (const double h : cvsm_detail::heading_probes(opt.heading, on_allowed_side(pose.heading))) {
    const CvsmPose trial = cvsm_detail::turned_in_place(model, spine, upright, on_allowed_side(h));
    probes.push_back({trial, cost_of(trial, to_params(trial), INT64_MAX)});
    if (probes.back().cost < probes[best].cost) best = probes.size() - 1;
  }
  // The silhouettes' pixels, whatever the pose.
  const XorCounts counts = evaluate(*trunk_search_model, probes[best].pose, INT64_MAX);
  const std::int64_t silhouette_px = counts.silhouette_px[0] + counts.silhouette_px[1];
  // The front range prefers facing the frontal camera (subject_heading.hpp).
  for (std::size_t i = 0; i < probes.size(); ++i)
    if (cvsm_detail::wrapped_heading(probes[i].pose.heading) ==
            on_allowed_side(cvsm_detail::preferred_heading(opt.heading, on_allowed_side(probes[best].pose.heading))) &&
        probes[best].cost >= cvsm_detail::cost_to_beat_facing(opt.heading, on_allowed_side(probes[best].pose.heading),
                                                              probes[i].cost, silhouette_px))
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

// Where the range does not take the side turned away (fixed, front):
// `s` at its heading against its mirror, added to the guard's evidence;
// once it says the subject faces away, the subject model is turned to
// that side (fitted as he stands) and held there, every posture lost
// (docs/cvsm.md, "Turned away from the range"). Returns evaluations.
// On the pair that completes the model (`completes`) a lean away is enough.
int CvsmTracker::Impl::weigh_facing(cvsm_detail::SubjectEstimate& s, bool completes) {
  if (opt.heading == HeadingRange::Any || !facing_guard.weighing()) return 0;
  const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(s, *cost, spec, spine);
  facing_guard.add(choice);
  if (facing_guard.says_away() || (completes && facing_guard.leans_away())) {
    held_away = true;
    away_followed = opt.heading == HeadingRange::Front && facing_guard.says_away();
    s.pose = cvsm_detail::turned_in_place(cvsm_detail::build(s, spec, spine), spine, s.pose, choice.away_heading);
  }
  return choice.evaluations;
}

// The options a pair's own first estimate is placed with: the subject
// model's — without a given stature the views contradicted (weighed for
// a man 250 mm shorter than in view, he led for his mirror and every pair
// was held turned away).
CvsmOptions CvsmTracker::Impl::placing_options() const {
  return subject->rejected_stature_mm ? without_given_body(opt) : opt;
}

// This pair's own first estimate at the heading the range allows nearest
// the subject's (its mirror when he is held turned away), shaped as the
// subject model so far: weighed from here, the side the model was refined
// at does not start ahead.
cvsm_detail::SubjectEstimate CvsmTracker::Impl::fresh_at_allowed_heading(const BitMask& frontal, const BitMask& lateral,
                                                                         double heading_deg) const {
  cvsm_detail::SubjectEstimate fresh =
      cvsm_detail::initial_subject(rig, spec, spine, placing_options(), frontal, lateral);
  fresh.measured_spine = subject->measured_spine;
  fresh.shape.posture = subject->shape.posture;
  // Turned away, the allowed heading is his reflection (180° − h): the one
  // whose frontal outline is his, which weigh_against_mirror weighs him
  // against. (His heading turned 180° weighed a subject at 240° as 60°
  // against 120°, both a third of a turn from him, and the allowed side won.)
  const double allowed = cvsm_detail::heading_allowed(opt.heading, heading_deg)
                             ? heading_deg
                             : cvsm_detail::wrapped_heading(180 - heading_deg);
  if (allowed != fresh.pose.heading)
    fresh.pose = cvsm_detail::turned_in_place(cvsm_detail::build(fresh, spec, spine), spine, fresh.pose, allowed);
  return fresh;
}

// Found again after he left the view (he may come back turned round):
// the sides weighed on this pair alone, the mirror believed when it leads
// by kAwayPreferenceFraction. Then held turned away as after the model.
// Not after a fit merely lost in view: on cameras tilted 45° one pair's
// lead strays past the margin, and 28496 tracked 22 % instead of 58 %.
void CvsmTracker::Impl::weigh_reacquired(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
  facing_guard.restart();
  const cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, pose.heading);
  const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(fresh, *cost, spec, spine);
  r.fit.candidates = r.fit.candidates.value_or(0) + choice.evaluations;
  facing_guard.add(choice);
  if (!facing_guard.says_away()) return;
  held_away = true;
  away_followed = false;
  pose = cvsm_detail::turned_in_place(model, spine, pose, choice.away_heading);
  facing_guard.restart();
}

// A pair tracked while the subject is held turned away: lost, flagged.
// Every kRecheckPairs the sides are weighed again on this pair (he may
// have turned round); once the allowed side leads, the pose is turned
// back to it and the next pair is tracked as usual.
void CvsmTracker::Impl::hold_turned_away(const BitMask& frontal, const BitMask& lateral, CvsmResult& r) {
  if (facing_guard.recheck_due()) {
    cvsm_detail::SubjectEstimate fresh = fresh_at_allowed_heading(frontal, lateral, pose.heading);
    const cvsm_detail::HeadingChoice choice = cvsm_detail::weigh_against_mirror(fresh, *cost, spec, spine);
    r.fit.candidates = r.fit.candidates.value_or(0) + choice.evaluations;
    facing_guard.add(choice);
    if (facing_guard.says_back()) {
      held_away = false;
      away_followed = false;
      pose = cvsm_detail::turned_in_place(model, spine, pose, choice.facing_heading);
      facing_guard.restart();
    } else if (facing_guard.leans_away()) {
      facing_guard.restart();  // still turned away: the next weighing starts afresh
    }
  }
  if (r.state == TrackingState::Tracking && !away_followed) {
    r.state = TrackingState::Lost;
    // Turned away says more than an unresolved twist (of a mirror image).
    if (!r.fit.flag || *r.fit.flag == kTwistUnresolvedFlag) r.fit.flag = std::string(kFacingAwayFlag);
  }
}

bool CvsmTracker::Impl::facing_settled() const {
  return opt.heading == HeadingRange::Any || facing_guard.says_allowed() || away_followed;
}

}  // namespace spinewatch
