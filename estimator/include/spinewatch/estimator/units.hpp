#pragma once
// Constants of unit conversion and physics, shared so that two sources
// never disagree on them (nor collide in a unity build).
#include <cmath>

namespace spinewatch {

inline constexpr double kRadPerDeg = M_PI / 180.0;
inline constexpr double kDegPerRad = 180.0 / M_PI;
inline constexpr double kGravity = 9.81;  // m/s²

}  // namespace spinewatch
