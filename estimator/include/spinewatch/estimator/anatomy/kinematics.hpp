#pragma once
// Segmental kinematics of the spine: a posture as rotations at each
// intervertebral joint plus a pelvis pose carrying L5.
//
// Angle conventions (degrees, world axes of docs/interfaces.md §1):
//   flexion  > 0: forward bend, the upper vertebra rotates about −Z
//            (its Y axis tips toward +X, anterior);
//   lateral  > 0: bend to the subject's right, rotation about +X
//            (Y tips toward +Z);
//   twist    > 0: axial rotation about +Y (anterior turns toward −Z, the
//            subject's left).
// A joint's rotation is R = Rz(−flexion) · Rx(lateral) · Ry(twist), applied
// about the joint centre (the midpoint of the two neutral body centres), in
// the lower vertebra's frame.
#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

struct JointAngles {
  double flexion = 0, lateral = 0, twist = 0;  // degrees
};

struct SegmentalMotion {
  std::array<JointAngles, kJointCount> joints{};  // T1-T2 first
  // Pelvis: rotation of L5 about its neutral body centre, then translation.
  JointAngles pelvis{};
  Eigen::Vector3d pelvis_translation = Eigen::Vector3d::Zero();
};

Eigen::Quaterniond joint_rotation(const JointAngles& a);
// The inverse of joint_rotation for a relative rotation (exact for the
// convention above, away from gimbal lock at 90° lateral).
JointAngles joint_angles(const Eigen::Quaterniond& relative);

// Poses every vertebra: L5 from the pelvis, then each joint upward.
SpinePose pose_spine(const SpinePose& neutral, const SegmentalMotion& motion);

// Spreads whole-spine angles over the joints in proportion to each joint's
// range of motion in the spec (flexion by the F+E range, lateral and twist
// by their one-side ranges): the way a trunk bend is shared between levels.
SegmentalMotion distribute(const SpineSpec& spec, double flexion_deg, double lateral_deg, double twist_deg);

// Relative rotation of vertebra i to vertebra i+1, as joint angles.
std::array<JointAngles, kJointCount> intervertebral_angles(const SpinePose& pose);

}  // namespace spinewatch
