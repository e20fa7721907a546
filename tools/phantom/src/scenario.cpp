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

// Moving limbs (LimbMotion): work and everyday movements whose arms, legs
// and head change the silhouettes as much as the trunk does.

// 0 before `a`, 1 after `b`, a smooth rise between.
double ramp(double u, double a, double b) {
  if (u <= a) return 0;
  if (u >= b) return 1;
  return 0.5 * (1.0 - std::cos(M_PI * (u - a) / (b - a)));
}
// A bump over [a, b] only.
double bump_in(double u, double a, double b) { return u <= a || u >= b ? 0.0 : bump((u - a) / (b - a)); }
constexpr double kRadToDeg = 180.0 / M_PI;

// Forwards to the bench in front: the right arm alone, then both; the trunk
// leans in as the arms go out, the elbows straighten.
constexpr double kReachElevation = 45, kReachFlexion = 25, kReachStraighten = -19;
TrunkMotion reach(int i, int n) {
  const double u = phase(i, n);
  return {.flexion_deg = kReachFlexion * (bump_in(u, 0, 0.5) + bump_in(u, 0.5, 1))};
}
LimbMotion reach_limbs(int i, int n) {
  const double u = phase(i, n);
  const double one = bump_in(u, 0, 0.5), both = bump_in(u, 0.5, 1);
  LimbMotion l;
  l.arms[1] = {kReachElevation * (one + both), 0, kReachStraighten * (one + both)};
  l.arms[0] = {kReachElevation * both, 0, kReachStraighten * both};
  l.head.flexion_deg = 15 * (one + both);
  return l;
}

TrunkMotion arms_overhead(int i, int n) { return {.flexion_deg = -6 * bump(phase(i, n))}; }
LimbMotion arms_overhead_limbs(int i, int n) {
  const double b = bump(phase(i, n));
  LimbMotion l;
  for (ArmMotion& arm : l.arms) arm = {170 * b, 25, -15 * b};
  l.head.flexion_deg = -15 * b;  // looking up at the hands
  return l;
}

// A box held in front of the chest, the trunk turning one way and the other.
TrunkMotion carry(int i, int n) {
  const double u = phase(i, n);
  return {.flexion_deg = -3, .twist_deg = 12 * wave(u, 1.0)};
}
LimbMotion carry_limbs(int i, int n) {
  LimbMotion l;
  for (ArmMotion& arm : l.arms) arm = {10, 0, 55};
  l.head.flexion_deg = 10;
  l.head.twist_deg = 6 * wave(phase(i, n), 1.0);
  l.carries_box = true;
  return l;
}

// Steps in place for two thirds (knees up in turn, arms swinging against
// them), then a step aside to the right: the right foot out, the body over
// it, the left foot after it.
constexpr double kStepAsideMm = 250, kHipHalfSpanMm = 82, kLegDropMm = 900;
TrunkMotion stride(int i, int n) {
  const double u = phase(i, n);
  const double aside = ramp(u, 0.67 + 0.33 * 0.35, 0.67 + 0.33 * 0.7);
  TrunkMotion m{.lateral_deg = -4 * bump_in(u, 0.67, 1)};
  m.sway_mm = Eigen::Vector3d(0, 0, kStepAsideMm * aside);
  return m;
}
LimbMotion stride_limbs(int i, int n) {
  const double u = phase(i, n);
  LimbMotion l;
  if (u < 0.67) {
    const double w = wave(u / 0.67, 3.0);  // three steps with each foot
    const double right = std::max(0.0, w), left = std::max(0.0, -w);
    l.legs[1] = {40 * right, 0, 65 * right};
    l.legs[0] = {40 * left, 0, 65 * left};
    l.arms[1] = {25 * (left - right), 0, 20};
    l.arms[0] = {25 * (right - left), 0, 20};
    return l;
  }
  const double v = (u - 0.67) / 0.33;
  const double right_foot = kHipHalfSpanMm + kStepAsideMm * ramp(v, 0, 0.35);
  const double pelvis = kStepAsideMm * ramp(v, 0.35, 0.7);
  const double left_foot = -kHipHalfSpanMm + kStepAsideMm * ramp(v, 0.7, 1.0);
  l.legs[1] = {0, kRadToDeg * std::atan((right_foot - pelvis - kHipHalfSpanMm) / kLegDropMm), 25 * bump_in(v, 0, 0.35)};
  l.legs[0] = {0, kRadToDeg * std::atan((pelvis - kHipHalfSpanMm - left_foot) / kLegDropMm), 25 * bump_in(v, 0.7, 1.0)};
  l.arms[1] = {12 * bump_in(v, 0, 0.7), 90, 0};  // a little out for balance
  return l;
}

// A lunge forwards on the right leg, the pelvis down and forwards, the trunk
// bending to the left with the right (far) arm overhead.
TrunkMotion lunge(int i, int n) {
  const double b = bump(phase(i, n));
  TrunkMotion m{.flexion_deg = 8 * b, .lateral_deg = -22 * b};
  m.sway_mm = Eigen::Vector3d(180 * b, -140 * b, 0);
  return m;
}
LimbMotion lunge_limbs(int i, int n) {
  const double b = bump(phase(i, n));
  LimbMotion l;
  l.legs[1] = {65 * b, 0, 75 * b};
  l.legs[0] = {-22 * b, 0, 35 * b};
  l.arms[1] = {165 * b, 70, -15 * b};
  l.arms[0] = {25 * b, 90, 30 * b};  // the near arm out a little, on the bent-to side
  l.head.lateral_deg = -10 * b;
  return l;
}

// Seated at a desk, forearms on it, typing: the fingers' work shows as a
// slight movement of the forearms; the head bowed to the screen and back.
TrunkMotion typing(int i, int n) {
  const double u = phase(i, n);
  return {.flexion_deg = 10 + 4 * wave(u, 1.0), .twist_deg = 3 * wave(u, 1.5, 0.2)};
}
LimbMotion typing_limbs(int i, int n) {
  const double u = phase(i, n);
  LimbMotion l;
  for (std::size_t k = 0; k < 2; ++k) l.arms[k] = {12, 0, 68 + 3 * wave(u, 6.0, 0.25 * double(k))};
  l.head.flexion_deg = 12 + 6 * wave(u, 1.0, 0.4);
  return l;
}

constexpr std::array<Scenario, 16> kScenarios = {{
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
    {"reach", "the right arm, then both, forwards to a bench and back, the trunk leaning in", 120, false, reach,
     reach_limbs, Furniture::Bench},
    {"arms_overhead", "both arms raised overhead and lowered, looking up", 90, false, arms_overhead,
     arms_overhead_limbs},
    {"carry", "a box held in front of the chest, the trunk turning +/-12 deg", 90, false, carry, carry_limbs},
    {"stride", "steps in place, then a step aside to the right", 120, false, stride, stride_limbs},
    {"lunge", "a lunge on the right leg with a side bend to the left, the right arm overhead", 90, false, lunge,
     lunge_limbs},
    {"typing", "seated at a desk that hides the legs, forearms on it, typing", 90, true, typing, typing_limbs,
     Furniture::Desk},
}};

}  // namespace

std::span<const Scenario> scenarios() { return kScenarios; }

const Scenario* find_scenario(std::string_view name) {
  for (const Scenario& s : kScenarios)
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace spinewatch::phantom
