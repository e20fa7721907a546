#include "cvsm/facing_check.hpp"

#include <vector>

namespace spinewatch::cvsm_detail {

HeadingChoice weigh_against_mirror(const SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec,
                                   const SpineSpec& spine) {
  SubjectEstimate allowed = s;
  SubjectEstimate mirror = s;
  mirror.pose = turned_in_place(build(s, spec, spine), spine, s.pose, wrapped_heading(s.pose.heading + 180));
  HeadingChoice choice;
  // Both from the same start: neither side is ahead by its convergence.
  for (int round = 0; round < kMirrorRefineRounds; ++round) {
    choice.evaluations += refine_subject(allowed, cost, spec, spine);
    choice.evaluations += refine_subject(mirror, cost, spec, spine);
  }
  std::vector<Eigen::Vector3d> points;
  auto counts_of = [&](const SubjectEstimate& e) {
    const BodyModel m = build(e, spec, spine);
    control_points(m, pose_vertebrae(m, spine, e.pose), points, {}, e.pose.heading);
    return cost.evaluate(m, points, INT64_MAX);
  };
  const XorCounts allowed_counts = counts_of(allowed);
  const std::int64_t mirror_cost = counts_of(mirror).total();
  choice.evaluations += 2;
  choice.silhouette_px = allowed_counts.silhouette_px[0] + allowed_counts.silhouette_px[1];
  choice.sides_compared = true;
  choice.facing_lead_px = mirror_cost - allowed_counts.total();
  choice.margin_px = choice.facing_lead_px < 0 ? -choice.facing_lead_px : choice.facing_lead_px;
  choice.facing_heading = allowed.pose.heading;
  choice.away_heading = mirror.pose.heading;
  return choice;
}

}  // namespace spinewatch::cvsm_detail
