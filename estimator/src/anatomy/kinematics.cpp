#include "spinewatch/estimator/anatomy/kinematics.hpp"

#include <cmath>

#include "spinewatch/estimator/units.hpp"

namespace spinewatch {

Eigen::Quaterniond joint_rotation(const JointAngles& a) {
  return Eigen::AngleAxisd(-a.flexion * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(a.lateral * kRadPerDeg, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(a.twist * kRadPerDeg, Eigen::Vector3d::UnitY());
}

JointAngles joint_angles(const Eigen::Quaterniond& relative) {
  // R = Rz(a)·Rx(b)·Ry(c): R21 = sin b, R20 = −cos b sin c, R22 = cos b cos c,
  // R01 = −sin a cos b, R11 = cos a cos b.
  const Eigen::Matrix3d R = relative.normalized().toRotationMatrix();
  const double b = std::asin(std::clamp(R(2, 1), -1.0, 1.0));
  const double c = std::atan2(-R(2, 0), R(2, 2));
  const double a = std::atan2(-R(0, 1), R(1, 1));
  return {-a / kRadPerDeg, b / kRadPerDeg, c / kRadPerDeg};
}

SpinePose pose_spine(const SpinePose& neutral, const SegmentalMotion& motion) {
  SpinePose pose;
  const Eigen::Quaterniond pelvis = joint_rotation(motion.pelvis);
  pose[kWaistIndex].q = pelvis;
  pose[kWaistIndex].body_center = neutral[kWaistIndex].body_center + motion.pelvis_translation;
  for (std::size_t i = kWaistIndex; i-- > 0;) {
    const VertebraPose& lower = pose[i + 1];
    const Eigen::Vector3d& p_low0 = neutral[i + 1].body_center;
    const Eigen::Vector3d& p_up0 = neutral[i].body_center;
    const Eigen::Vector3d centre0 = 0.5 * (p_low0 + p_up0);
    const Eigen::Quaterniond rj = joint_rotation(motion.joints[i]);
    // Neutral orientations are identity, so neutral offsets are already in
    // the lower vertebra's local frame.
    pose[i].q = (lower.q * rj).normalized();
    pose[i].body_center = lower.body_center + lower.q * (centre0 - p_low0) + pose[i].q * (p_up0 - centre0);
  }
  return pose;
}

SegmentalMotion distribute(const SpineSpec& spec, double flexion_deg, double lateral_deg, double twist_deg) {
  double sum_f = 0, sum_l = 0, sum_t = 0;
  for (const auto& j : spec.joints) {
    sum_f += j.flexion_deg;
    sum_l += j.lateral_deg;
    sum_t += j.axial_deg;
  }
  SegmentalMotion m;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    m.joints[i].flexion = flexion_deg * spec.joints[i].flexion_deg / sum_f;
    m.joints[i].lateral = lateral_deg * spec.joints[i].lateral_deg / sum_l;
    m.joints[i].twist = twist_deg * spec.joints[i].axial_deg / sum_t;
  }
  return m;
}

std::array<JointAngles, kJointCount> intervertebral_angles(const SpinePose& pose) {
  std::array<JointAngles, kJointCount> out;
  for (std::size_t i = 0; i < kJointCount; ++i) out[i] = joint_angles(pose[i + 1].q.conjugate() * pose[i].q);
  return out;
}

}  // namespace spinewatch
