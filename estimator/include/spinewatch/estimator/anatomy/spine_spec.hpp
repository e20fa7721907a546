#pragma once
// The generic spine's figures (config/spine-generic.toml, embedded at build
// time) and the neutral standing pose they give. Shared by the phantom
// (ground truth), the CVSM (its deformations) and the accurate model.
#include <array>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

inline constexpr std::size_t kJointCount = kVertebraCount - 1;  // T1-T2 … L4-L5

struct VertebraSpec {
  std::string name;
  double height_mm = 0, width_mm = 0, depth_mm = 0;
  double spacing_mm = 0;  // body-centre distance to the next vertebra below
};

struct JointSpec {
  std::string name;          // "T1-T2"
  double flexion_deg = 0;    // flexion + extension range together
  double lateral_deg = 0;    // one side
  double axial_deg = 0;      // one side
  double k_axial_n_per_mm = 0;
};

struct SpineSpec {
  double reference_height_mm = 1750;
  double l5_height_fraction = 0.575;
  double kyphosis_deg = 40;
  double lordosis_deg = 45;
  std::array<VertebraSpec, kVertebraCount> vertebrae;
  std::array<JointSpec, kJointCount> joints;
};

// Parses a spine file; `source` names it in error messages.
Result<SpineSpec> parse_spine_spec(std::string_view toml_text, std::string_view source);
// config/spine-generic.toml as built into the binary.
const SpineSpec& generic_spine_spec();
std::string_view generic_spine_toml();

// The neutral standing pose of a subject of `height_mm` whose L5 body centre
// is at `l5_center`: body centres in the sagittal plane through L5 following
// the kyphosis and lordosis of the spec, spacings scaled by
// height / reference height, all orientations identity (docs/interfaces.md §1).
SpinePose neutral_pose(const SpineSpec& spec, double height_mm, const Eigen::Vector3d& l5_center);
// Same, with the L5 height from the spec (x = z = 0).
SpinePose neutral_pose(const SpineSpec& spec, double height_mm);

// Body sizes scaled to a subject of `height_mm`.
double size_scale(const SpineSpec& spec, double height_mm);

}  // namespace spinewatch
