// The trunk's searches (tracker_impl.hpp): candidates scored by the XOR
// cost with the translation's and the limbs' penalties, the local search
// from the last pose, the global one at (re)acquisition, and the axial
// twist's sign.
#include <cmath>

#include "cvsm/tracker_impl.hpp"

namespace spinewatch {

double CvsmTracker::Impl::translation_penalty(const PoseParams& a) const {
  if (!anchored) return 0;
  const double d2 = (Eigen::Vector3d(a[5], a[6], a[7]) - home).squaredNorm();
  return kTranslationPxPerMm2 * d2 / cost->row_step();
}

namespace {

// A limb the views cannot see (hidden behind the trunk, beyond the
// image's border) leaves the XOR flat along its angles: this small pull
// towards the neutral limbs settles it there instead of wherever the
// search last left it, and a limb that is seen outweighs it many times
// (an arm raised 60° moves some 200 search pixels; the pull costs 18).
// In the cost's sampled pixels, per degree².
constexpr double kLimbPxPerDeg2 = 0.02;

}  // namespace

double CvsmTracker::Impl::limb_penalty(const LimbPose& limbs) const {
  if (opt.limbs == LimbMode::Fixed) return 0;
  double sum = 0;
  for (const double a : to_limb_params(limbs)) sum += a * a;
  return kLimbPxPerDeg2 * sum / cost->row_step();
}

std::int64_t CvsmTracker::Impl::cost_of(const PoseParams& a, std::int64_t limit) {
  return cost_of(trunk_pose(a), a, limit);
}
std::int64_t CvsmTracker::Impl::cost_of(const CvsmPose& p, const PoseParams& a, std::int64_t limit) {
  const auto penalty = static_cast<std::int64_t>(translation_penalty(a) + limb_penalty(p.limbs));
  if (penalty >= limit) return penalty;
  return evaluate(*trunk_search_model, p, limit - penalty).total() + penalty;
}

struct CvsmTracker::Impl::Candidates {
  Impl& impl;
  PoseParams best;
  std::int64_t best_cost;
  int evaluations = 1;
  Candidates(Impl& i, const PoseParams& start) : impl(i), best(start), best_cost(i.cost_of(start, INT64_MAX)) {}
  void try_one(const PoseParams& a) {
    ++evaluations;
    const std::int64_t c = impl.cost_of(a, best_cost);
    if (c < best_cost) {
      best_cost = c;
      best = a;
    }
  }
};

// Local coarse-to-fine search around `start` (and a constant-velocity
// prediction from it).
int CvsmTracker::Impl::local_search(int budget) {
  Candidates c(*this, to_params(pose));
  if (phase == Phase::Predicting) {
    PoseParams predicted = c.best, prev = to_params(previous);
    for (std::size_t i = 0; i < predicted.size(); ++i) predicted[i] += c.best[i] - prev[i];
    c.try_one(predicted);
  }
  // From the prediction the residual motion is small: a 2° / 5 mm step,
  // then a half step only for what moved.
  const PoseParams step{2, 2, 2, 2, 1, 5, 3, 5};
  auto d = coordinate_descent(c.best, c.best_cost, step, 2, budget - c.evaluations,
                              [&](const PoseParams& a, std::int64_t limit) { return cost_of(a, limit); }, true);
  pose = trunk_pose(d.params);
  searched_cost = d.best;
  return c.evaluations + d.evaluations;
}

// Whole-range search over trunk flexion and lateral bending, then a wide
// local search.
int CvsmTracker::Impl::global_search(int budget) {
  PoseParams base = to_params(pose);
  base[0] = base[1] = base[2] = base[3] = base[4] = 0;
  Candidates c(*this, base);
  for (double f = -20; f <= 80; f += 10)
    for (double l = -30; l <= 30; l += 10) {
      PoseParams a = base;
      a[0] = f;
      a[1] = l;
      c.try_one(a);
    }
  const PoseParams step{8, 6, 8, 6, 4, 40, 20, 40};
  auto d = coordinate_descent(c.best, c.best_cost, step, 6, budget - c.evaluations,
                              [&](const PoseParams& a, std::int64_t limit) { return cost_of(a, limit); });
  pose = trunk_pose(d.params);
  return c.evaluations + d.evaluations;
}

namespace {

// Axial twist: the two views see its magnitude (a twisted thorax and the
// arms hanging from it narrow the frontal outline and spread the lateral
// one) far better than its sign: under a parallel projection a twist of
// +θ and −θ draw the same pair of outlines, and only perspective (the
// nearer shoulder larger), the forearms reaching forward and the trunk's
// front/back asymmetry about the spine tell them apart. So once a search
// settles on a twist of kTwistSignatureDeg or more, the mirrored twist
// (every other parameter kept) is scored too: the better of the two is
// kept, and when they score within kTwistSignMarginPx the sign is not
// resolved and the pair is flagged "twist_unresolved" (docs/cvsm.md,
// "Axial twist"). Two evaluations, on the search's rows.
constexpr double kTwistSignatureDeg = 6;

}  // namespace

CvsmTracker::Impl::TwistCheck CvsmTracker::Impl::check_twist_sign(int& candidates) {
  TwistCheck t;
  const PoseParams a = to_params(pose);
  if (std::abs(a[2]) < kTwistSignatureDeg) return t;
  PoseParams mirrored = a;
  mirrored[2] = -a[2];
  const std::int64_t kept = cost_of(a, INT64_MAX), other = cost_of(mirrored, INT64_MAX);
  candidates += 2;
  t.checked = true;
  if (other < kept) pose = trunk_pose(mirrored);
  t.margin_px = std::abs(other - kept);
  return t;
}

}  // namespace spinewatch
