#pragma once
// Which way the subject faces (docs/cvsm.md, "Heading"): the full circle
// tried when the subject model is started and at every (re)acquisition,
// both views together deciding front from back.
#include <cstdint>
#include <vector>

#include "spinewatch/estimator/cvsm/heading_range.hpp"

#include "cvsm/subject_estimate.hpp"

namespace spinewatch::cvsm_detail {

// Headings tried around the full circle, degrees apart.
inline constexpr double kHeadingProbeDeg = 30;

// The headings probed round the circle: every kHeadingProbeDeg from
// `around` (Any), or the front half only, −90…90° (Front).
std::vector<double> heading_probes(HeadingRange range, double around);
// Whether a heading is one the range lets the subject face.
bool heading_allowed(HeadingRange range, double heading_deg);

// The station as installed: the worker on the frontal camera's axis. With
// the front range he faces it, over the full circle he faces it or turns
// his back to it (preferred_heading), and another heading is taken only
// when it explains this fraction more of the silhouettes' pixels than the
// preferred one nearest it does — twenty times the cost's pair-to-pair
// noise (kHeadingMarginFraction). A body the model draws badly (a box
// carried, a cluttered room, a seated worker behind a desk) costs a third
// or more of its silhouettes at every heading, and there a turn of 30° won
// by 3–4 % (docs/cvsm.md, "Heading"); a subject really turned 30° wins by
// 9 %, 90° by 40 %. Front against back is decided apart
// (kAwayPreferenceFraction).
inline constexpr double kFrontPreferenceFraction = 0.05;
// The heading the range prefers nearest `heading_deg`: facing the frontal
// camera (0) or, over the full circle, the back to it (180) — the worker
// on the frontal camera's axis, as the station is installed.
double preferred_heading(HeadingRange range, double heading_deg);
// The cost `heading_deg` must reach to be taken over the preferred heading
// nearest it (preferred_heading) at `facing_cost`: the cost itself where
// the range has no preference or the heading is the preferred one.
std::int64_t cost_to_beat_facing(HeadingRange range, double heading_deg, std::int64_t facing_cost,
                                 std::int64_t silhouette_px);

// Angular distance of two headings, 0…180°.
double heading_apart(double a, double b);
// A heading in (−180, 180].
double wrapped_heading(double heading_deg);

// The pose turned to `heading_deg` about its hip joints, its translation
// moved so the trunk's centre line stays where it is (the silhouettes
// measured it, whichever way the body faces).
CvsmPose turned_in_place(const BodyModel& model, const SpineSpec& spine, const CvsmPose& pose, double heading_deg);

// The XOR of one standing subject moves by 0.2–0.3 % of the silhouettes'
// pixels from pair to pair with the same pose (sensor noise, flicker).
// Four times that: two headings closer in cost are not told apart, and a
// step of the heading is taken only when it gains more (docs/cvsm.md,
// "Heading"). A few degrees of heading draw nearly the outline of a few
// degrees of axial twist; at a quarter of this the heading followed the
// twist and the twist's published value went wrong.
inline constexpr double kHeadingMarginFraction = 0.01;

// Front from back, over the full circle, decided on converged fits: the
// best probe and its mirror (turned 180°) each get this many rounds of the
// shape fit (refine_subject's default budget) before they are compared.
// A probe's 60 evaluations start from the first pair's direct
// measurements, which a box carried at the belly or clutter grown onto the
// silhouette put off the trunk; from there the side whose start happened
// to lie nearer converged first and won by 11–16 % of the silhouettes'
// pixels on bodies that faced the other way (docs/cvsm.md, "Heading").
// Refined three rounds, the right side won on every one measured.
inline constexpr int kMirrorRefineRounds = 3;

struct HeadingChoice {
  int evaluations = 0;
  // The best cost of a heading 90° or more from the chosen one minus the
  // chosen one's, in the cost's pixels: how clearly the views tell this
  // side from the other.
  std::int64_t margin_px = 0;
  std::int64_t silhouette_px = 0;  // both views, in the same pixels
  // Over the full circle, the two sides as compared on converged fits:
  // the cost of the side turned away from the frontal camera minus the
  // facing side's (positive: facing fits better), and each side's heading.
  // The tracker sums them over the pairs it searched (FrontBackEvidence).
  bool sides_compared = false;
  std::int64_t facing_lead_px = 0;
  double facing_heading = 0, away_heading = 180;
  bool resolved() const {
    return static_cast<double>(margin_px) >= kHeadingMarginFraction * static_cast<double>(silhouette_px);
  }
};

// Over the full circle, the side turned away from the frontal camera is
// taken only when it fits better than the facing side by this fraction of
// the silhouettes' pixels (the facing side by kHeadingMarginFraction):
// the station is installed with the frontal camera in front of the worker,
// and a flipped heading publishes a side bend on the wrong side. A subject
// really turned away leads by 4.0–4.5 % (docs/cvsm.md, "Heading"); a
// seated typist behind a desk whom the model took for a short standing man
// led turned away by 0.4–1.9 % on each of his first pairs.
inline constexpr double kAwayPreferenceFraction = 0.025;

// Front from back summed over pairs (range any): each search's mirror
// comparison added, and a side taken only once the sum leads by the
// side's fraction of the summed silhouettes; in between, undecided. A
// subject the model draws about as well both ways is searched again on
// every building pair, and one pair of many passing the margin by chance
// had turned him round.
struct FrontBackEvidence {
  std::int64_t facing_lead_px = 0, silhouette_px = 0;
  void add(const HeadingChoice& choice) {
    facing_lead_px += choice.facing_lead_px;
    silhouette_px += choice.silhouette_px;
  }
  bool decided() const {
    const auto lead = static_cast<double>(facing_lead_px), px = static_cast<double>(silhouette_px);
    return lead >= kHeadingMarginFraction * px || -lead >= kAwayPreferenceFraction * px;
  }
  // The heading of the side the sum favours, from the latest comparison.
  double heading(const HeadingChoice& latest) const {
    return facing_lead_px > 0 ? latest.facing_heading : latest.away_heading;
  }
};

// The subject's heading from its first pair: every kHeadingProbeDeg, the
// estimate turned there and its shape refined (`budget_each` evaluations);
// the best heading then settled alone to a degree, held to the preferred
// heading nearest it unless it beats it by kFrontPreferenceFraction and,
// over the full circle, compared with its mirror on converged fits
// (kMirrorRefineRounds), which also gives the margin. The range is
// `options.heading`. Only the heading (and
// the translation that keeps the trunk in place) is kept in `subject`:
// its shape is refined as before, at that heading.
HeadingChoice choose_heading(SubjectEstimate& subject, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                             const CvsmOptions& options, int budget_each = 60);

}  // namespace spinewatch::cvsm_detail
