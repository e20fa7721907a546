#pragma once
// The scripted movements a phantom recording shows (docs/phantom.md).
#include <array>
#include <cstdint>
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

// The limbs and head at one instant, as angles from the rest pose the
// phantom has always had (arms hanging 7° out with the elbows a little
// bent, legs straight or seated, the head in line with T1), degrees.
// Index of arms and legs: 0 left, 1 right. They only change the
// silhouettes; the ground truth stays the spine.
struct ArmMotion {
  double elevation_deg = 0;  // the upper arm raised from hanging (180: overhead)
  double swing_deg = 0;      // the plane it rises in: 0 forwards, 90 out to the side
  double elbow_deg = 0;      // further elbow flexion (negative straightens it)
};
struct LegMotion {
  double flexion_deg = 0;    // the thigh forwards at the hip
  double abduction_deg = 0;  // the thigh out to the side
  double knee_deg = 0;       // the shin back at the knee
};
struct HeadMotion {
  double flexion_deg = 0, lateral_deg = 0, twist_deg = 0;  // on the neck, relative to T1
};
struct LimbMotion {
  std::array<ArmMotion, 2> arms{};
  std::array<LegMotion, 2> legs{};
  HeadMotion head;
  bool carries_box = false;  // a box held between the hands (a solid of the person)
};

// Furniture in front of the subject: part of the room (in the empty scene
// too), never of the person, and it hides what is behind it.
enum class Furniture : std::uint8_t {
  None,
  Desk,   // a desk, top 730 mm above the floor, with a front and side panels
  Bench,  // a workbench, top 900 mm above the floor, with a front panel
};

struct Scenario {
  std::string_view name;
  std::string_view description;
  int default_frames = 90;  // person frames at 30 fps, after the empty ones
  bool seated = false;      // overrides the subject's posture
  // The motion at person frame `i` of `n`.
  TrunkMotion (*motion)(int i, int n) = nullptr;
  // The limbs at person frame `i` of `n`; none: the rest pose, the legs
  // where the neutral pose puts them whatever the sway (as always).
  LimbMotion (*limbs)(int i, int n) = nullptr;
  Furniture furniture = Furniture::None;  // what stands in front of the subject unless told otherwise
};

inline constexpr double kPhantomFps = 30.0;

std::span<const Scenario> scenarios();
const Scenario* find_scenario(std::string_view name);

}  // namespace spinewatch::phantom
