#include "cvsm/outline_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace spinewatch::cvsm_detail {

double ParamPrior::at(const std::array<double, 8>& a) const {
  double sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += weight[k] * (a[k] - centre[k]) * (a[k] - centre[k]);
  return sum;
}

OutlineFit::OutlineFit(XorCost& cost, const BodyModel& model, std::array<const SilhouetteEdges*, 2> edges, int width,
                       const OutlineFitSettings& settings)
    : cost_(cost), model_(model), edges_(edges), last_x_(static_cast<float>(width - 1)), settings_(settings) {}

double OutlineFit::measure(const Params& a, const PointsOf& points_of) {
  points_of(a, points_);
  matched_.clear();
  distance_.clear();
  if (!cost_.outline(model_, points_, ends_)) return std::numeric_limits<double>::infinity();
  const double delta = settings_.huber_px;
  double sum = 0;
  const std::array<const BitMask*, 2> hidden{cost_.hidden(View::Frontal), cost_.hidden(View::Lateral)};
  for (const OutlineEnd& e : ends_) {
    if (e.x <= 0.0f || e.x >= last_x_) continue;
    // An end where an occluder hides the person (XorCost::set_hidden)
    // has no edge to meet: counted as unmatched, the objective would
    // change with how many ends the pose puts below a desk's edge.
    if (const BitMask* h = hidden[e.view]; h != nullptr && h->get(static_cast<int>(std::lround(e.x)), e.row)) continue;
    const float edge = edges_[e.view]->nearest(e.row, e.x, e.right, settings_.window_px);
    if (std::isnan(edge)) {
      sum += settings_.window_px;
      continue;
    }
    const double d = static_cast<double>(e.x) - static_cast<double>(edge);
    sum += std::abs(d) <= delta ? 0.5 * d * d : delta * (std::abs(d) - 0.5 * delta);
    matched_.push_back(e);
    distance_.push_back(d);
  }
  return sum;
}

double OutlineFit::objective(const Params& a, const PointsOf& points_of, const ParamPrior& prior) {
  return measure(a, points_of) + prior.at(a);
}

int OutlineFit::refine(Params& a, int steps, const PointsOf& points_of, const ParamPrior& prior) {
  if (steps <= 0) return 0;
  double f = measure(a, points_of) + prior.at(a);
  int scans = 1;
  if (!std::isfinite(f)) return scans;
  using Vector8 = Eigen::Matrix<double, 8, 1>;
  using Matrix8 = Eigen::Matrix<double, 8, 8>;
  for (int step = 0; step < steps; ++step) {
    // Each end's derivative: the span that bounds it read again with one
    // parameter nudged (an end whose span leaves its row is left out).
    const auto n = static_cast<Eigen::Index>(matched_.size());
    jacobian_.resize(n, 8);
    nudged_.resize(matched_.size());
    base_points_ = points_;  // the last measure() was at a
    for (std::size_t k = 0; k < 8; ++k) {
      const auto column = static_cast<Eigen::Index>(k);
      if (settings_.probe[k] == 0) {
        jacobian_.col(column).setZero();
        continue;
      }
      if (const int axis = settings_.shifts_along[k]; axis >= 0) {
        points_ = base_points_;
        for (Eigen::Vector3d& p : points_) p[axis] += settings_.probe[k];
      } else {
        Params nudged = a;
        nudged[k] += settings_.probe[k];
        points_of(nudged, points_);
      }
      ++scans;
      if (!cost_.scan(model_, points_)) return scans;
      cost_.span_ends(matched_, nudged_.data());
      for (Eigen::Index i = 0; i < n; ++i)
        jacobian_(i, column) = static_cast<double>(nudged_[static_cast<std::size_t>(i)] - matched_[static_cast<std::size_t>(i)].x) / settings_.probe[k];
    }
    // Huber by reweighting: the normal equations of Σ w·d², w = 1 within
    // huber_px and huber_px/|d| beyond (0 for an end left out); the prior
    // adds its own quadratic.
    weight_.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double d = distance_[static_cast<std::size_t>(i)];
      const bool spanned = jacobian_.row(i).allFinite();
      if (!spanned) jacobian_.row(i).setZero();
      weight_(i) = !spanned ? 0.0 : std::abs(d) <= settings_.huber_px ? 1.0 : settings_.huber_px / std::abs(d);
    }
    const Eigen::Map<const Eigen::VectorXd> distance(distance_.data(), n);
    Matrix8 h = jacobian_.transpose() * weight_.asDiagonal() * jacobian_;
    Vector8 g = jacobian_.transpose() * weight_.cwiseProduct(distance);
    for (std::size_t k = 0; k < 8; ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      h(i, i) += 2 * prior.weight[k];
      g(i) += 2 * prior.weight[k] * (a[k] - prior.centre[k]);
      // Levenberg's damping: a direction the outline hardly sees (the
      // model's flat ones) is not thrown far by a little noise.
      h(i, i) = h(i, i) * 1.01 + 1e-9;
    }
    const Vector8 delta = -h.ldlt().solve(g);
    if (!delta.allFinite()) return scans;
    double scale = 1;
    for (std::size_t k = 0; k < 8; ++k) {
      const double size = std::abs(delta(static_cast<Eigen::Index>(k)));
      if (size > settings_.max_step[k]) scale = std::min(scale, settings_.max_step[k] / size);
    }
    bool moved = false;
    for (int halving = 0; halving < 3 && !moved; ++halving, scale *= 0.5) {
      Params trial = a;
      for (std::size_t k = 0; k < 8; ++k) trial[k] += scale * delta(static_cast<Eigen::Index>(k));
      const double ft = measure(trial, points_of) + prior.at(trial);
      ++scans;
      if (ft < f) {
        a = trial;
        f = ft;
        moved = true;
      }
    }
    // The outline measured last is a rejected trial's: no further step
    // can start from it.
    if (!moved) break;
  }
  return scans;
}

}  // namespace spinewatch::cvsm_detail
