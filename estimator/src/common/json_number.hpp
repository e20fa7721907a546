#pragma once
// Numbers as the estimator's JSON lines print them.
#include <cmath>

namespace spinewatch::detail {

// Rounds v to a decimal quantum (0.01, 1e-6, …) so that lines stay short
// and carry no digits below what the method resolves. Dividing by the exact
// integer 1/quantum (rather than multiplying by the inexact quantum) gives
// the double nearest the decimal, which prints short.
inline double round_to(double v, double quantum) {
  const double inverse = std::round(1.0 / quantum);
  return std::round(v * inverse) / inverse;
}

}  // namespace spinewatch::detail
