#pragma once
// The scripted movements a phantom recording shows (docs/phantom.md).
#include <optional>
#include <span>
#include <string_view>

#include <Eigen/Core>

namespace spinewatch::phantom {

// Whole-trunk angles at one instant (degrees, conventions of
// anatomy/kinematics.hpp) and a small body sway (mm, world).
struct TrunkMotion {
  double flexion_deg = 0, lateral_deg = 0, twist_deg = 0;
  Eigen::Vector3d sway_mm = Eigen::Vector3d::Zero();
};

struct Scenario {
  std::string_view name;
  std::string_view description;
  int default_frames = 90;  // person frames at 30 fps, after the empty ones
  bool seated = false;      // overrides the subject's posture
  // The motion at person frame `i` of `n`.
  TrunkMotion (*motion)(int i, int n) = nullptr;
};

inline constexpr double kPhantomFps = 30.0;

std::span<const Scenario> scenarios();
const Scenario* find_scenario(std::string_view name);

}  // namespace spinewatch::phantom
