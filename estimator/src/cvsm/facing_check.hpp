#pragma once
// Front from back where the configured heading range does not take the side
// turned away from the frontal camera ([cvsm] heading = "fixed" or "front";
// docs/cvsm.md, "Heading", "Turned away from the range"). The fit there holds
// the subject on the side the range allows; a worker with his back to the
// frontal camera is then fitted as his own mirror image — a forward bend read
// as an extension, a side bend on the wrong side — and each posture is
// confidently wrong. The views do tell the sides apart (the lateral outline
// shows the profile), so the allowed side is weighed against its mirror, and
// when the mirror wins the posture is not published as tracking.
#include <cstdint>

#include "cvsm/subject_estimate.hpp"
#include "cvsm/subject_heading.hpp"

namespace spinewatch::cvsm_detail {

// The subject at its heading h (one the range allows) against the side
// turned away: the heading whose frontal view is the same (180° − h, the
// frontal camera cannot tell them apart; the lateral one can), each side as
// three headings 30° apart around its own (those the side holds), all
// refined kMirrorRefineRounds rounds of the shape fit from the same start
// and the best of each side compared on the converged costs:
// `facing_lead_px` is the side turned away's cost minus the allowed side's
// (positive: the allowed side fits better), `facing_heading` and
// `away_heading` the best heading of each. Weighed against h + 180° alone, a
// subject turned 120–150° whom the fit faced 60–30° towards the camera was
// compared with a heading neither view confuses with his, and was tracked
// as his reflection. `s` is not changed.
HeadingChoice weigh_against_mirror(const SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec,
                                   const SpineSpec& spine);

// A subject chosen standing at heading h (one the range allows) that sits
// with his back to the frontal camera: seated, facing the other way, his
// thighs point where a seated model facing h would have its back, so the
// seated model loses at h and the standing one wins there (seated_flexion
// turned 180°: a man of 1 689 mm taken for a standing one of 1 325, every
// posture 160–210 mm off, a forward bend read as an extension). Standing
// against its mirror, neither side's straight legs say which way he faces.
// So the posture is chosen again at the reflection (180° − h, the heading
// whose frontal view is the same); when seated there fits better than
// standing at h, `s` becomes that seated estimate turned back to h, and the
// facing side is then weighed seated (weigh_against_mirror), where the
// thighs tell it. Returns the cost evaluations spent.
int seat_if_turned_away(SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                        const CvsmOptions& options);

// What the tracker knows of the side the subject faces when the range does
// not take the side turned away. Summed over the pairs weighed, as over the
// full circle (FrontBackEvidence): the mirror is believed only when the sum
// leads by kAwayPreferenceFraction of the summed silhouettes, the allowed
// side by kHeadingMarginFraction.
class FacingGuard {
 public:
  // While the subject model is built: each pair weighed until decided.
  bool weighing() const { return evidence_.silhouette_px == 0 || !evidence_.decided(); }
  void add(const HeadingChoice& choice) {
    evidence_.add(choice);
    ++weighed_;
  }
  // The subject faces away: the sum says the mirror fits better by
  // kAwayPreferenceFraction (weighing then stops).
  bool says_away() const { return evidence_.decided() && evidence_.facing_lead_px < 0; }
  // The sum leads for the allowed side by kHeadingMarginFraction: what an
  // early (provisional) posture waits for.
  bool says_allowed() const { return evidence_.decided() && evidence_.facing_lead_px > 0; }
  // The sum leans away by the margin that decides the facing side
  // (kHeadingMarginFraction) without reaching kAwayPreferenceFraction: the
  // verdict on the pair that completes the subject model.
  bool leans_away() const { return lead_fraction() <= -kHeadingMarginFraction; }
  // Back to the allowed side, while held turned away: the sum leads for it
  // by kAwayPreferenceFraction, the margin the side turned away needs —
  // leaving the hold publishes postures, and a wrong side is the worst.
  // Two weighings at least (a second apart): one pair's lead moves by 2 %
  // and more from pair to pair on a subject turned 150–210°.
  bool says_back() const { return weighed_ >= 2 && lead_fraction() >= kAwayPreferenceFraction; }
  // After the model is built, while the subject is held turned away: a
  // pair weighed every kRecheckPairs (he may turn round); the evidence
  // summed since the last decision.
  static constexpr int kRecheckPairs = 15;
  bool recheck_due() { return ++pairs_away_ % kRecheckPairs == 0; }
  void restart() {
    evidence_ = {};
    weighed_ = 0;
  }
  // The summed lead of the allowed side over its mirror, as a fraction of
  // the summed silhouettes (0 with nothing weighed).
  double lead_fraction() const {
    return evidence_.silhouette_px > 0
               ? static_cast<double>(evidence_.facing_lead_px) / static_cast<double>(evidence_.silhouette_px)
               : 0.0;
  }

 private:
  FrontBackEvidence evidence_;
  int weighed_ = 0;  // pairs weighed into evidence_
  int pairs_away_ = 0;
};

}  // namespace spinewatch::cvsm_detail
