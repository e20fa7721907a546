// The outline refinement after the search (tracker_impl.hpp; docs/cvsm.md,
// "Outline refinement"; outline_fit.hpp): one step by default (refine_steps).
#include "cvsm/outline_fit.hpp"
#include "cvsm/tracker_impl.hpp"

namespace spinewatch {

// The searches compare candidates on whole pixels, so the pose they
// return rests on whichever stair of that cost their path reached; this
// settles it between them on the outline (outline_fit.hpp). Derivatives
// over a quarter of a search step; a step moves a parameter at most one
// search step (2°; 5 / 3 / 5 mm).
// Not with articulated limbs: there the limbs' search, started from the
// refined trunk, no longer finds a raised arm (CvsmLimbs.ArticulatedFit…:
// the right shoulder at −16° for the truth's 90°), and the trunk's search
// keeps its whole budget.
bool CvsmTracker::Impl::refining() const {
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
CvsmResult CvsmTracker::Impl::settle(const BitMask& frontal, const BitMask& lateral, int candidates,
                                     std::string_view flag, bool searched_globally) {
  if (!refining()) return finish(TrackingState::Tracking, candidates, flag);
  if (opt.limbs == LimbMode::Auto) {
    CvsmResult searched = finish(TrackingState::Tracking, candidates, flag);
    if (!refine_follows(searched.fit.cost)) return searched;
    ++candidates;  // that evaluation
  }
  anchored = !searched_globally;  // refined as it was searched
  // With auto limbs the search kept its whole budget, and the next pair's
  // starts from where it ended, not from the refined pose: refined starts
  // led the searches elsewhere (docs/cvsm.md, "Outline refinement": reach,
  // 28496, drifted to 61 mm over six pairs with the arm out). With fixed
  // limbs the search was cut to its coarse steps and goes on from the
  // refined pose.
  if (opt.limbs == LimbMode::Auto) searched_pose = pose;
  candidates += refine(frontal, lateral, opt.refine_steps);
  anchored = true;
  return finish(TrackingState::Tracking, candidates, flag);
}

bool CvsmTracker::Impl::refine_follows(double fixed_cost) const {
  return fixed_cost < best_building_cost + kArmsEvidenceRise;
}

int CvsmTracker::Impl::refine(const BitMask& frontal, const BitMask& lateral, int steps) {
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

}  // namespace spinewatch
