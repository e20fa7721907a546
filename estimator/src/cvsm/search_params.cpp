#include "cvsm/search_params.hpp"

namespace spinewatch::cvsm_detail {

PoseParams to_params(const CvsmPose& p) {
  const double total = p.flexion + p.pelvis_flexion;
  return {total, p.lateral, p.twist, p.pelvis_flexion - kPelvisShare * total, p.pelvis_lateral,
          p.translation.x(), p.translation.y(), p.translation.z()};
}
CvsmPose to_pose(const PoseParams& a, const LimbPose& limbs) {
  CvsmPose p;
  p.limbs = limbs;
  p.pelvis_flexion = kPelvisShare * a[0] + a[3];
  p.flexion = a[0] - p.pelvis_flexion;
  p.lateral = a[1];
  p.twist = a[2];
  p.pelvis_lateral = a[4];
  p.translation = {a[5], a[6], a[7]};
  return p;
}

LimbParams to_limb_params(const LimbPose& l) {
  LimbParams a{};
  for (std::size_t s = 0; s < 2; ++s) {
    const LimbPose::Side& d = l.side[s];
    const std::size_t o = 6 * s;
    a[o + 0] = d.shoulder_flexion;
    a[o + 1] = d.shoulder_abduction;
    a[o + 2] = d.elbow;
    a[o + 3] = d.hip_flexion;
    a[o + 4] = d.hip_abduction;
    a[o + 5] = d.knee;
  }
  a[12] = l.head_flexion;
  a[13] = l.head_lateral;
  a[14] = l.head_turn;
  return a;
}
LimbPose to_limbs(const LimbParams& a) {
  LimbPose l;
  for (std::size_t s = 0; s < 2; ++s) {
    LimbPose::Side& d = l.side[s];
    const std::size_t o = 6 * s;
    d.shoulder_flexion = a[o + 0];
    d.shoulder_abduction = a[o + 1];
    d.elbow = a[o + 2];
    d.hip_flexion = a[o + 3];
    d.hip_abduction = a[o + 4];
    d.knee = a[o + 5];
  }
  l.head_flexion = a[12];
  l.head_lateral = a[13];
  l.head_turn = a[14];
  return l;
}

bool in_range(const LimbParams& a) {
  for (std::size_t i = 0; i < kLimbParams; ++i)
    if (a[i] < kLimbRange[i][0] || a[i] > kLimbRange[i][1]) return false;
  return true;
}

}  // namespace spinewatch::cvsm_detail
