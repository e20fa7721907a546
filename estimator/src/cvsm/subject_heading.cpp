#include "cvsm/subject_heading.hpp"

#include <cmath>
#include <vector>

namespace spinewatch::cvsm_detail {
namespace {

// The mean of the trunk's vertebra rings in the horizontal plane.
Eigen::Vector3d trunk_centre(const BodyModel& model, const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (std::size_t p = 0; p < model.planes.size(); ++p) {
    if (!model.planes[p].vertebra) continue;
    for (std::size_t k = 0; k < kControlPoints; ++k, ++n) sum += points[p * kControlPoints + k];
  }
  return n > 0 ? Eigen::Vector3d(sum / n) : sum;
}

XorCounts estimate_cost(const SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                        std::vector<Eigen::Vector3d>& points) {
  const BodyModel m = build(s, spec, spine);
  control_points(m, pose_vertebrae(m, spine, s.pose), points, {}, s.pose.heading);
  return cost.evaluate(m, points, INT64_MAX);
}

// A probe of choose_heading: its heading, cost and refined estimate.
struct Tried {
  double heading;
  std::int64_t cost;
  SubjectEstimate estimate;
};

}  // namespace

double heading_apart(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return d > 180 ? 360 - d : d;
}

double wrapped_heading(double h) {
  h = std::fmod(h, 360.0);
  if (h > 180) h -= 360;
  if (h <= -180) h += 360;
  return h;
}

CvsmPose turned_in_place(const BodyModel& model, const SpineSpec& spine, const CvsmPose& pose, double heading_deg) {
  std::vector<Eigen::Vector3d> points;
  control_points(model, pose_vertebrae(model, spine, pose), points, pose.limbs, pose.heading);
  const Eigen::Vector3d before = trunk_centre(model, points);
  CvsmPose turned = pose;
  turned.heading = heading_deg;
  control_points(model, pose_vertebrae(model, spine, turned), points, turned.limbs, turned.heading);
  const Eigen::Vector3d shift = before - trunk_centre(model, points);
  turned.translation.x() += shift.x();
  turned.translation.z() += shift.z();
  return turned;
}

std::vector<double> heading_probes(HeadingRange range, double around) {
  std::vector<double> out;
  if (range == HeadingRange::Fixed) {
    out.push_back(0);
  } else if (range == HeadingRange::Front) {
    for (double h = -90; h <= 90; h += kHeadingProbeDeg) out.push_back(h);
  } else {
    for (double h = 0; h < 360; h += kHeadingProbeDeg) out.push_back(wrapped_heading(around + h));
  }
  return out;
}

double preferred_heading(HeadingRange range, double heading_deg) {
  return range == HeadingRange::Any && std::abs(wrapped_heading(heading_deg)) > 90 ? 180 : 0;
}

std::int64_t cost_to_beat_facing(HeadingRange range, double heading_deg, std::int64_t facing_cost,
                                 std::int64_t silhouette_px) {
  if (range == HeadingRange::Fixed || wrapped_heading(heading_deg) == preferred_heading(range, heading_deg))
    return facing_cost;
  return facing_cost - static_cast<std::int64_t>(kFrontPreferenceFraction * static_cast<double>(silhouette_px));
}

bool heading_allowed(HeadingRange range, double heading_deg) {
  if (range == HeadingRange::Fixed) return wrapped_heading(heading_deg) == 0;
  return range == HeadingRange::Any || std::abs(wrapped_heading(heading_deg)) <= 90;
}

namespace {

// The chosen heading against its mirror, each refined from its own probe
// by kMirrorRefineRounds of the shape fit: the better is left in `best`,
// and the margin is how much better it fits.
HeadingChoice settle_front_from_back(SubjectEstimate& best, const std::vector<Tried>& tried, XorCost& cost,
                                     const CvsmSpec& spec, const SpineSpec& spine, HeadingChoice choice) {
  const double mirror_heading = wrapped_heading(best.pose.heading + 180);
  const Tried* nearest = &tried.front();
  for (const Tried& t : tried)
    if (heading_apart(t.heading, mirror_heading) < heading_apart(nearest->heading, mirror_heading)) nearest = &t;
  SubjectEstimate mirror = nearest->estimate;
  mirror.pose = turned_in_place(build(mirror, spec, spine), spine, mirror.pose, mirror_heading);
  SubjectEstimate chosen = best;
  for (int round = 0; round < kMirrorRefineRounds; ++round) {
    choice.evaluations += refine_subject(chosen, cost, spec, spine);
    choice.evaluations += refine_subject(mirror, cost, spec, spine);
  }
  std::vector<Eigen::Vector3d> points;
  const std::int64_t chosen_cost = estimate_cost(chosen, cost, spec, spine, points).total();
  const std::int64_t mirror_cost = estimate_cost(mirror, cost, spec, spine, points).total();
  choice.evaluations += 2;
  const bool chosen_faces = std::abs(wrapped_heading(chosen.pose.heading)) <= 90;
  choice.sides_compared = true;
  choice.facing_lead_px = chosen_faces ? mirror_cost - chosen_cost : chosen_cost - mirror_cost;
  choice.facing_heading = chosen_faces ? chosen.pose.heading : mirror.pose.heading;
  choice.away_heading = chosen_faces ? mirror.pose.heading : chosen.pose.heading;
  if (mirror_cost < chosen_cost) best = mirror;
  choice.margin_px = std::abs(mirror_cost - chosen_cost);
  return choice;
}

}  // namespace

HeadingChoice choose_heading(SubjectEstimate& s, XorCost& cost, const CvsmSpec& spec, const SpineSpec& spine,
                             const CvsmOptions& options, int budget_each) {
  const HeadingRange range = options.heading;
  HeadingChoice choice;
  std::vector<Eigen::Vector3d> points;
  const BodyModel model = build(s, spec, spine);
  std::vector<Tried> tried;
  SubjectEstimate best = s;
  std::int64_t best_cost = INT64_MAX;
  // The probes at the preferred headings (0, and 180 over the full circle).
  struct Preferred {
    SubjectEstimate estimate;
    std::int64_t cost = INT64_MAX, silhouette_px = 0;
  };
  Preferred facing, back;
  for (const double h : heading_probes(range, 0)) {
    SubjectEstimate candidate = s;
    candidate.pose = turned_in_place(model, spine, s.pose, h);
    choice.evaluations += refine_subject(candidate, cost, spec, spine, budget_each);
    const XorCounts counts = estimate_cost(candidate, cost, spec, spine, points);
    const std::int64_t c = counts.total();
    ++choice.evaluations;
    tried.push_back({candidate.pose.heading, c, candidate});
    if (c < best_cost) {
      best_cost = c;
      best = candidate;
      choice.silhouette_px = counts.silhouette_px[0] + counts.silhouette_px[1];
    }
    if (wrapped_heading(h) == 0 || wrapped_heading(h) == 180)
      (wrapped_heading(h) == 0 ? facing : back) = {candidate, c, counts.silhouette_px[0] + counts.silhouette_px[1]};
  }
  // Between the probes: the heading alone, halving steps from a quarter
  // of their spacing down to a degree, each past the cost's noise.
  const BodyModel best_model = build(best, spec, spine);
  const auto gain = static_cast<std::int64_t>(kHeadingMarginFraction * static_cast<double>(choice.silhouette_px));
  for (double step = kHeadingProbeDeg / 4; step >= 1; step /= 2)
    for (const double dir : {1.0, -1.0}) {
      if (!heading_allowed(range, best.pose.heading + dir * step)) continue;
      SubjectEstimate trial = best;
      trial.pose = turned_in_place(best_model, spine, best.pose, wrapped_heading(best.pose.heading + dir * step));
      const std::int64_t c = estimate_cost(trial, cost, spec, spine, points).total();
      ++choice.evaluations;
      if (c < best_cost - gain) {
        best_cost = c;
        best = trial;
        break;
      }
    }
  // The front range prefers facing the frontal camera, the full circle
  // facing it or the back to it (kFrontPreferenceFraction), judged on the
  // settled heading: a few degrees' turn must win as much as a probe's.
  const Preferred& axis = preferred_heading(range, best.pose.heading) == 0 ? facing : back;
  if (axis.cost != INT64_MAX &&
      best_cost >= cost_to_beat_facing(range, best.pose.heading, axis.cost, axis.silhouette_px)) {
    best = axis.estimate;
    best_cost = axis.cost;
    choice.silhouette_px = axis.silhouette_px;
  }
  std::int64_t other_side = INT64_MAX;
  for (const Tried& t : tried)
    if (heading_apart(t.heading, best.pose.heading) >= 90) other_side = std::min(other_side, t.cost);
  choice.margin_px = other_side == INT64_MAX ? INT64_MAX : other_side - best_cost;
  if (range == HeadingRange::Any) choice = settle_front_from_back(best, tried, cost, spec, spine, choice);
  if (best.pose.heading != s.pose.heading) s.pose = turned_in_place(model, spine, s.pose, best.pose.heading);
  return choice;
}

}  // namespace spinewatch::cvsm_detail
