#pragma once
// The pose refined on the outline, after the search (config [cvsm]
// refine_steps; docs/cvsm.md, "Outline refinement").
//
// Why: the search compares candidates on whole pixels (about 6.7 mm at
// 2 m), so its cost is a staircase in the pose and the pose it returns rests
// on whichever stair its path reached. Here every end of the model's
// outline on a row (cvsm/outline_ends.hpp) is pulled towards the
// silhouette's nearest edge of its kind on that row
// (cvsm/silhouette_edges.hpp): those ends move continuously with the pose,
// so the fit can settle between the stairs. Gauss–Newton, because the
// residuals are many (a thousand ends) and the parameters eight: each
// parameter's derivative is one more scan with it nudged, a step solves
// an 8 × 8 system, where a sweep of one-parameter trials on the XOR
// (an earlier form of this refinement) took 25 evaluations for the same gain.
//
// The distances are Huber-weighted (quadratic within huber_px, linear
// beyond): an arm the silhouette lacks, or a shadow it has, pulls no harder
// than a pixel's worth. An end with no edge of its kind within window_px
// counts as window_px and does not pull. Ends clamped to the image's edge
// do not count: the person may go on beyond it; nor do ends on pixels an
// occluder hides (XorCost::set_hidden), which the XOR does not count
// either.
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "cvsm/outline_ends.hpp"
#include "cvsm/silhouette_edges.hpp"
#include "cvsm/xor_cost.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"

namespace spinewatch::cvsm_detail {

struct OutlineFitSettings {
  std::array<double, 8> probe{};     // how far a parameter is nudged for its derivative
  std::array<double, 8> max_step{};  // how far one step may move each parameter
  // A parameter that moves every control point along a world axis (0, 1,
  // 2; −1: not so): its nudged points are the last ones shifted, not
  // computed again through the pose (a fifth of a derivative's pass).
  std::array<int, 8> shifts_along{-1, -1, -1, -1, -1, -1, -1, -1};
  int window_px = 6;
  double huber_px = 1.0;
};

// A pull of the parameters towards `centre`: Σ weight·(a − centre)², in the
// objective's units (pixels); the tracker anchors the hips with it.
struct ParamPrior {
  std::array<double, 8> weight{};
  std::array<double, 8> centre{};
  double at(const std::array<double, 8>& a) const;
};

class OutlineFit {
 public:
  using Params = std::array<double, 8>;
  // The model's world control points at a (the tracker's pose → vertebrae →
  // control points).
  using PointsOf = std::function<void(const Params&, std::vector<Eigen::Vector3d>&)>;

  OutlineFit(XorCost& cost, const BodyModel& model, std::array<const SilhouetteEdges*, 2> edges, int width,
             const OutlineFitSettings& settings);
  // Up to `steps` Gauss–Newton steps from a, each halved up to twice until
  // it lowers the objective; a never ends worse than it started. Returns
  // the scans spent (each a cost evaluation's scan conversion).
  int refine(Params& a, int steps, const PointsOf& points_of, const ParamPrior& prior);
  // The objective at a: Σ Huber(distance) over the matched ends,
  // window_px for each unmatched one, plus the prior.
  double objective(const Params& a, const PointsOf& points_of, const ParamPrior& prior);

 private:
  // Outline at a, distances to the edges; the objective without the prior.
  double measure(const Params& a, const PointsOf& points_of);

  XorCost& cost_;
  const BodyModel& model_;
  std::array<const SilhouetteEdges*, 2> edges_;
  float last_x_;  // ends at or beyond [0, last_x_] are clamped to the image
  OutlineFitSettings settings_;
  std::vector<Eigen::Vector3d> points_, base_points_;
  std::vector<OutlineEnd> ends_;
  std::vector<OutlineEnd> matched_;    // the ends with an edge in reach, from the last measure()
  std::vector<double> distance_;       // theirs: end − edge, pixels
  std::vector<float> nudged_;          // their ends with one parameter nudged
  Eigen::Matrix<double, Eigen::Dynamic, 8> jacobian_;
  Eigen::VectorXd weight_;
};

}  // namespace spinewatch::cvsm_detail
