#include "spinewatch/estimator/load/exposure_summary.hpp"

#include <cmath>

namespace spinewatch {

InclinationZone inclination_zone(double deg, const ErgonomicLimits& l) {
  if (deg < -l.extension_margin_deg) return InclinationZone::Extension;
  if (deg <= l.inclination_ok_deg) return InclinationZone::Upright;
  if (deg <= l.inclination_max_deg) return InclinationZone::Flexed;
  return InclinationZone::Stooped;
}

std::string_view zone_key(InclinationZone zone) {
  switch (zone) {
    case InclinationZone::Extension: return "extension";
    case InclinationZone::Upright: return "0_20";
    case InclinationZone::Flexed: return "20_60";
    case InclinationZone::Stooped: return "over_60";
  }
  return "?";
}

int rula_trunk_score(const TrunkAngles& a, const ErgonomicLimits& l) {
  const double flexion = std::abs(a.inclination_deg);
  int score = flexion <= l.reba_upright_deg ? 1 : a.inclination_deg <= 20 ? 2 : a.inclination_deg <= 60 ? 3 : 4;
  if (std::abs(a.twist_deg) > l.reba_twist_side_deg) ++score;
  if (std::abs(a.lateral_deg) > l.reba_twist_side_deg) ++score;
  return score;
}

std::string_view to_string(SummaryScope scope) { return scope == SummaryScope::Shift ? "shift" : "interval"; }

}  // namespace spinewatch
