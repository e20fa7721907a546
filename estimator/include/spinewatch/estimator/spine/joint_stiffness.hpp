#pragma once
// Bending and torsional stiffness of each intervertebral joint of the
// accurate model, from published in-vitro load–displacement tests
// (config/spine-stiffness.toml, embedded at build time; every row names its
// source there). Kept apart from the range-of-motion table of the spine
// spec, which shapes the phantom's and the CVSM's motion: the model's
// stiffness must not come from the motion it is scored against.
#include <array>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct JointStiffness {
  std::string name;                  // "T1-T2"
  double moment_nm = 0;              // pure moment of the test, each direction
  double flexion_extension_deg = 0;  // flexion + extension range at ±moment
  double lateral_deg = 0;            // one side, at the moment
  double axial_deg = 0;              // one side, at the moment
  std::string source;                // key of the source in the file's header

  // Secant stiffness moment / one-side range about the lower vertebra's
  // X (lateral bend), Y (twist), Z (flexion) axes, N·m/rad; flexion uses
  // half the flexion + extension range.
  Eigen::Vector3d nm_per_rad() const;
};

using JointStiffnessTable = std::array<JointStiffness, kJointCount>;

// Parses a stiffness file; `source` names it in error messages. Every joint
// T1-T2 … L4-L5 must appear once, in order; unknown keys are errors.
Result<JointStiffnessTable> parse_joint_stiffness(std::string_view toml_text, std::string_view source);
// config/spine-stiffness.toml as built into the binary.
const JointStiffnessTable& generic_joint_stiffness();
std::string_view joint_stiffness_toml();

}  // namespace spinewatch
