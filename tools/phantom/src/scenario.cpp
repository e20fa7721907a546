#include "spinewatch/phantom/scenario.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace spinewatch::phantom {
namespace {

// Position in the movement, 0 at the first person frame and 1 at the last.
double phase(int i, int n) { return n > 1 ? double(i) / double(n - 1) : 0.0; }
// Smooth 0 → 1 → 0 over the whole movement (zero velocity at both ends).
double bump(double u) { return 0.5 * (1.0 - std::cos(2.0 * M_PI * u)); }
double wave(double u, double cycles, double offset = 0) { return std::sin(2.0 * M_PI * (cycles * u + offset)); }

TrunkMotion upright(int i, int n) {
  // Quiet standing: a fraction of a degree and a few millimetres of sway.
  const double u = phase(i, n) * double(n) / kPhantomFps;  // seconds
  TrunkMotion m;
  m.flexion_deg = 0.8 * std::sin(2 * M_PI * 0.25 * u);
  m.lateral_deg = 0.5 * std::sin(2 * M_PI * 0.35 * u + 1.0);
  m.sway_mm = Eigen::Vector3d(3.0 * std::sin(2 * M_PI * 0.2 * u), 0, 2.0 * std::sin(2 * M_PI * 0.3 * u + 0.5));
  return m;
}
TrunkMotion flexion(int i, int n) { return {.flexion_deg = 50 * bump(phase(i, n))}; }
TrunkMotion lateral_left(int i, int n) { return {.lateral_deg = -25 * bump(phase(i, n))}; }
TrunkMotion lateral_right(int i, int n) { return {.lateral_deg = 25 * bump(phase(i, n))}; }
TrunkMotion twist(int i, int n) { return {.twist_deg = 20 * wave(phase(i, n), 1.0)}; }
TrunkMotion combined(int i, int n) {
  const double u = phase(i, n);
  return {.flexion_deg = 40 * bump(u), .lateral_deg = 12 * bump(u), .twist_deg = 10 * wave(u, 1.0)};
}
TrunkMotion seated_flexion(int i, int n) { return {.flexion_deg = 40 * bump(phase(i, n))}; }
TrunkMotion sway(int i, int n) {
  const double u = phase(i, n);
  TrunkMotion m{.flexion_deg = 6 * wave(u, 2.0), .lateral_deg = 5 * wave(u, 3.0, 0.1), .twist_deg = 6 * wave(u, 1.5, 0.3)};
  m.sway_mm = Eigen::Vector3d(8 * wave(u, 1.0), 0, 6 * wave(u, 1.3, 0.2));
  return m;
}
TrunkMotion fast(int i, int n) {
  // 40° in 0.5 s (15 frames) and back in 0.5 s, centred in the recording,
  // whatever its length.
  constexpr int kHalf = 15;
  const int start = std::max(0, n / 2 - kHalf);
  const int k = i - start;
  if (k < 0 || k > 2 * kHalf) return {};
  return {.flexion_deg = 40 * bump(double(k) / double(2 * kHalf))};
}

// A working shift in miniature (docs/exposure.md): postures held in each
// ISO 11226 trunk zone and repeated side bends and twists, with quick
// (0.5 s) moves between them, so the time in each zone is known from the
// script. Times are seconds of a 120 s movement, stretched over however
// many frames are asked for (3600 frames: two minutes at 30 fps).
struct Hold {
  double until_s;  // held until here, after a 0.5 s move from the previous hold
  double flexion_deg, lateral_deg, twist_deg;
};
constexpr double kShiftLength_s = 120, kShiftMove_s = 0.5;
constexpr std::array<Hold, 27> kShiftHolds = {{
    {8, 0, 0, 0},     {20, 45, 0, 0},   {26, 0, 0, 0},    {42, 75, 0, 0},   {48, 0, 0, 0},
    {56, -15, 0, 0},  {60, 0, 0, 0},    {62, 0, 30, 0},   {64, 0, 0, 0},    {66, 0, 30, 0},
    {68, 0, 0, 0},    {70, 0, -30, 0},  {72, 0, 0, 0},    {74, 0, 0, 20},   {76, 0, 0, 0},
    {78, 0, 0, -20},  {80, 0, 0, 0},    {82, 0, 0, 20},   {84, 0, 0, 0},    {94, 100, 0, 0},
    {100, 0, 0, 0},   {112, 50, 0, 0},  {114, 0, 0, 0},   {116, 40, 0, 0},  {117, 0, 0, 0},
    {119, 20, 15, 15}, {120, 0, 0, 0},
}};
TrunkMotion shift(int i, int n) {
  const double t = phase(i, n) * kShiftLength_s;
  Hold from{0, 0, 0, 0};
  for (const Hold& h : kShiftHolds) {
    if (t <= h.until_s) {
      const double u = std::clamp((t - from.until_s) / kShiftMove_s, 0.0, 1.0);
      const double w = 0.5 * (1.0 - std::cos(M_PI * u));  // smooth start and stop
      return {.flexion_deg = from.flexion_deg + w * (h.flexion_deg - from.flexion_deg),
              .lateral_deg = from.lateral_deg + w * (h.lateral_deg - from.lateral_deg),
              .twist_deg = from.twist_deg + w * (h.twist_deg - from.twist_deg)};
    }
    from = h;
  }
  return {};
}

constexpr std::array<Scenario, 10> kScenarios = {{
    {"upright", "standing still, tiny natural sway", 90, false, upright},
    {"flexion", "trunk flexion 0 -> 50 deg -> 0 (2/3 spine, 1/3 pelvis)", 90, false, flexion},
    {"lateral_left", "lateral bend to the left 0 -> 25 deg -> 0", 90, false, lateral_left},
    {"lateral_right", "lateral bend to the right 0 -> 25 deg -> 0", 90, false, lateral_right},
    {"twist", "axial twist 0 -> +20 -> -20 -> 0 deg", 90, false, twist},
    {"combined", "flexion to 40 deg with 12 deg lateral bend and +/-10 deg twist", 120, false, combined},
    {"seated_flexion", "seated subject, trunk flexion 0 -> 40 deg -> 0", 90, true, seated_flexion},
    {"sway", "small oscillations in flexion, lateral bend and twist with body sway", 120, false, sway},
    {"fast", "a 40 deg forward bend in 0.5 s and back in 0.5 s", 60, false, fast},
    {"shift", "a shift in miniature: holds in every trunk zone, side bends, twists (--frames 3600: two minutes)", 120,
     false, shift},
}};

}  // namespace

std::span<const Scenario> scenarios() { return kScenarios; }

const Scenario* find_scenario(std::string_view name) {
  for (const Scenario& s : kScenarios)
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace spinewatch::phantom
