#include "spinewatch/estimator/anatomy/worker.hpp"

#include <fmt/format.h>

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

WorkerCheck check_known_worker(const KnownWorker& w) {
  // Adults in ANSUR II: C7 at 0.85–0.89 of the stature, the crest 400–460 mm
  // (±25) below C7. The bounds leave room for any adult and catch a value
  // typed in the wrong field or unit.
  if (w.c7_height_mm && w.stature_mm && *w.c7_height_mm > *w.stature_mm - 100)
    return {false, fmt::format("c7_height_mm: {:.0f} mm is not at least 100 mm below the stature ({:.0f} mm)",
                               *w.c7_height_mm, *w.stature_mm)};
  if (w.iliac_crest_height_mm && w.c7_height_mm && *w.iliac_crest_height_mm > *w.c7_height_mm - 250)
    return {false, fmt::format("iliac_crest_height_mm: {:.0f} mm is not at least 250 mm below c7_height_mm ({:.0f} mm)",
                               *w.iliac_crest_height_mm, *w.c7_height_mm)};
  if (w.iliac_crest_height_mm && w.stature_mm && *w.iliac_crest_height_mm > 0.7 * *w.stature_mm)
    return {false, fmt::format("iliac_crest_height_mm: {:.0f} mm is above 0.7 of the stature ({:.0f} mm)",
                               *w.iliac_crest_height_mm, *w.stature_mm)};
  return {};
}

}  // namespace spinewatch
