#include "spinewatch/estimator/anatomy/worker.hpp"

namespace spinewatch {

std::string_view to_string(BodyValueSource source) {
  switch (source) {
    case BodyValueSource::Given: return "given";
    case BodyValueSource::Measured: return "measured";
    case BodyValueSource::Estimated: return "estimated";
  }
  return "estimated";
}

double estimated_mass_kg(double stature_mm) {
  const double metres = stature_mm / 1000.0;
  return kMedianBmi * metres * metres;
}

}  // namespace spinewatch
