#pragma once
// Coarse-to-fine coordinate descent: each parameter in turn tries ±step and
// keeps going while that improves; steps halve after each sweep. The cost
// callback gets the best cost so far as its limit, so a candidate can be
// abandoned as soon as it cannot win. Then, on a continuous cost, sweeps
// of parabolic steps that settle between the descent's steps.
#include <algorithm>
#include <array>
#include <cstdint>

namespace spinewatch::cvsm_detail {

template <std::size_t N, class Cost>
struct Descent {
  std::array<double, N> params;
  std::int64_t best;
  int evaluations = 0;
};

// With `refine_moved_only`, finer levels revisit only the parameters that
// moved at a coarser one (the tracker's frame-to-frame search: a parameter
// that did not gain at the coarse step is already within it of its best).
template <std::size_t N, class Cost>
Descent<N, Cost> coordinate_descent(std::array<double, N> params, std::int64_t best, std::array<double, N> step,
                                    int levels, int budget, Cost&& cost, bool refine_moved_only = false) {
  Descent<N, Cost> d{params, best, 0};
  std::array<bool, N> moved{};
  for (int level = 0; level < levels && d.evaluations < budget; ++level) {
    for (std::size_t i = 0; i < N && d.evaluations < budget; ++i) {
      if (step[i] == 0) continue;
      if (refine_moved_only && level > 0 && !moved[i]) continue;
      const auto before = d.params[i];
      for (double dir : {1.0, -1.0}) {
        bool improved = false;
        for (int k = 0; k < 4 && d.evaluations < budget; ++k) {
          auto trial = d.params;
          trial[i] += dir * step[i];
          ++d.evaluations;
          const std::int64_t c = cost(trial, d.best);
          if (c >= d.best) break;
          d.best = c;
          d.params = trial;
          improved = true;
        }
        if (improved) break;  // no point trying the other direction
      }
      if (d.params[i] != before) moved[i] = true;
    }
    for (auto& s : step) s *= 0.5;
  }
  return d;
}

// Sweeps of parabolic steps on a cost that changes continuously: each
// parameter in turn is tried at ± its step and moved to the best of those
// two, where it was, and the vertex of the parabola through the three (when
// it opens upwards; clamped to the step, and evaluated). Steps halve after
// each sweep. Returns the evaluations spent.
template <std::size_t N, class Cost>
int parabolic_sweeps(std::array<double, N>& params, double& best, std::array<double, N> step, int sweeps, Cost&& cost) {
  int evaluations = 0;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (std::size_t i = 0; i < N; ++i) {
      if (step[i] == 0) continue;
      const std::array<double, N> start = params;
      const double here = best;
      std::array<double, N> trial = start;
      trial[i] = start[i] + step[i];
      const double plus = cost(trial);
      if (plus < best) best = plus, params = trial;
      trial[i] = start[i] - step[i];
      const double minus = cost(trial);
      if (minus < best) best = minus, params = trial;
      evaluations += 2;
      const double curvature = plus + minus - 2 * here;
      if (curvature <= 0) continue;
      const double t = std::clamp(0.5 * (minus - plus) / curvature, -1.0, 1.0);
      if (t == 1.0 || t == -1.0 || t == 0.0) continue;  // already tried
      trial[i] = start[i] + t * step[i];
      const double vertex = cost(trial);
      ++evaluations;
      if (vertex < best) best = vertex, params = trial;
    }
    for (auto& s : step) s *= 0.5;
  }
  return evaluations;
}

}  // namespace spinewatch::cvsm_detail
