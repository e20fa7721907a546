#include "cvsm/facing_check.hpp"

#include <cmath>
#include <vector>

#include "cvsm/posture_hidden.hpp"

namespace spinewatch::cvsm_detail {

HeadingChoice weigh_against_mirror(const SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec,
                                   const SpineSpec& spine) {
  // Below an occluder's edge the two sides' thighs differ (towards the
  // camera or away, turned or not): every column the edge cuts the person
  // on is hidden, as for the standing-or-seated choice (posture_hidden.hpp).
  // Hidden only on the straight run's columns, a seated man at his given
  // stature turned 30° had his thighs charged beside the run where the
  // desk hides them, and his mirror won by 3 % of the silhouettes: his
  // seated flexion behind a desk was published as his mirror image,
  // 118–160 mm off (docs/cvsm.md, "Turned away from the range").
  const CutSpanHidden cut(cost);
  const BodyModel model = build(s, spec, spine);
  // Each side as three headings 30° apart, so that neither side gains by
  // having more tries: the allowed one around the subject's, the other
  // around its reflection (180° − h, the heading whose frontal view is
  // the same), each kept where the range puts it.
  std::vector<SubjectEstimate> sides[2];
  const double centre[2] = {s.pose.heading, wrapped_heading(180 - s.pose.heading)};
  for (int side = 0; side < 2; ++side)
    for (const double d : {0.0, -30.0, 30.0}) {
      const double h = wrapped_heading(centre[side] + d);
      if ((std::abs(h) <= 90) != (side == 0) || (side == 1 && std::abs(h) == 90)) continue;
      SubjectEstimate e = s;
      e.pose = turned_in_place(model, spine, s.pose, h);
      sides[side].push_back(e);
    }
  HeadingChoice choice;
  // Every one from the same start: neither side is ahead by its convergence.
  for (int round = 0; round < kMirrorRefineRounds; ++round)
    for (auto& side : sides)
      for (SubjectEstimate& e : side) choice.evaluations += refine_subject(e, cost, spec, spine);
  std::vector<Eigen::Vector3d> points;
  auto counts_of = [&](const SubjectEstimate& e) {
    const BodyModel m = build(e, spec, spine);
    control_points(m, pose_vertebrae(m, spine, e.pose), points, {}, e.pose.heading);
    return cost.evaluate(m, points, INT64_MAX);
  };
  std::int64_t best_cost[2] = {INT64_MAX, INT64_MAX};
  const SubjectEstimate* best[2] = {&sides[0].front(), &sides[1].front()};
  XorCounts allowed_counts;
  for (int side = 0; side < 2; ++side)
    for (const SubjectEstimate& e : sides[side]) {
      const XorCounts c = counts_of(e);
      ++choice.evaluations;
      if (c.total() < best_cost[side]) {
        best_cost[side] = c.total();
        best[side] = &e;
        if (side == 0) allowed_counts = c;
      }
    }
  const SubjectEstimate allowed = *best[0];
  const SubjectEstimate mirror = *best[1];
  const std::int64_t mirror_cost = best_cost[1];
  choice.silhouette_px = allowed_counts.silhouette_px[0] + allowed_counts.silhouette_px[1];
  choice.sides_compared = true;
  choice.facing_lead_px = mirror_cost - allowed_counts.total();
  choice.margin_px = choice.facing_lead_px < 0 ? -choice.facing_lead_px : choice.facing_lead_px;
  choice.facing_heading = allowed.pose.heading;
  choice.away_heading = mirror.pose.heading;
  return choice;
}

int seat_if_turned_away(SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                        const CvsmOptions& options) {
  if (options.posture || s.shape.posture != SubjectPosture::Standing) return 0;
  std::vector<Eigen::Vector3d> points;
  const std::int64_t standing_cost = subject_cost(s, cost, spec, spine, points, INT64_MAX);
  SubjectEstimate away = s;
  away.pose = turned_in_place(build(s, spec, spine), spine, s.pose, wrapped_heading(180 - s.pose.heading));
  const int evaluations = choose_posture(away, cost, spec, spine, options) + 2;
  if (away.shape.posture != SubjectPosture::Seated ||
      subject_cost(away, cost, spec, spine, points, INT64_MAX) >= standing_cost)
    return evaluations;
  const double allowed = s.pose.heading;
  s = away;
  s.pose = turned_in_place(build(away, spec, spine), spine, away.pose, allowed);
  return evaluations;
}

}  // namespace spinewatch::cvsm_detail
