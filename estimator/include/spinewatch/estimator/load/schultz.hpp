#pragma once
// Compressive load on each vertebra from the posture: Schultz's equilibrium
// of the paper's Eqs. 21–23 with segment weights from body-segment fractions.
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Eq. 21–23 inputs: weights in N, lever arms in any one length unit,
// positive anterior of the vertebra (l_E: the erector's, posterior).
struct SchultzInputs {
  double w_trunk = 0, w_head = 0, w_left_arm = 0, w_right_arm = 0;
  double l_erector = 0, l_trunk = 0, l_head = 0, l_left_arm = 0, l_right_arm = 0;
};
struct SchultzResult {
  double erector_n = 0;      // E, Eq. 22
  double compression_n = 0;  // C, Eq. 21 / 23
};
// Eq. 23 as written; E may come out negative (a net extensor moment).
SchultzResult schultz(const SchultzInputs& in);

struct LoadParams {
  double body_mass_kg = 75;
  double reference_height_mm = 1750, height_mm = 1750;  // offsets scale by height / reference
  double head_neck = 0.081, thorax = 0.216, abdomen = 0.139;
  double upper_arm = 0.028, forearm = 0.016, hand = 0.006;  // each side
  Eigen::Vector3d head_com_mm{15, 200, 0};  // in T1's frame, from its body centre
  Eigen::Vector3d shoulder_mm{20, 0, 180};  // in T1's frame (Z: right; mirrored for the left)
  double arm_com_drop_mm = 290;
  double trunk_com_anterior_mm = 34;
  double erector_lever_mm = 135;
};

Result<LoadParams> parse_load_params(std::string_view toml_text, std::string_view source);
const LoadParams& default_load_params();  // config/segments.toml, embedded
std::string_view segments_toml();

// The Schultz inputs at vertebra `level` of `pose`: the weight above its
// inferior endplate (head, arms, trunk slices down to and including this
// vertebra) and the sagittal lever arms — horizontal distance, along the
// pelvis's (L5's) anterior axis, from the vertebra's body centre to each
// segment's centre of mass.
SchultzInputs schultz_inputs(const SpinePose& pose, std::size_t level, const LoadParams& params);
// Compression per vertebra, T1…L5. Erector force is not allowed to push
// (E ≥ 0): with the load behind the spine the compression is the weight.
std::vector<LevelLoad> compute_loads(const SpinePose& pose, const LoadParams& params);

}  // namespace spinewatch
