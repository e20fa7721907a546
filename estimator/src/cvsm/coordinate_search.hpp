#pragma once
// Coarse-to-fine coordinate descent: each parameter in turn tries ±step and
// keeps going while that improves; steps halve after each sweep. The cost
// callback gets the best cost so far as its limit, so a candidate can be
// abandoned as soon as it cannot win.
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

}  // namespace spinewatch::cvsm_detail
