#pragma once
// The subject's body posed for one instant: the ground-truth spine and the
// solids the renderer draws around it.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/phantom/scenario.hpp"
#include "spinewatch/phantom/subject.hpp"

namespace spinewatch::phantom {

// A convex body part given by points on its surface; its image is the
// convex hull of their projections.
// Grey levels of the clothing and skin; the renderer lightens each part's
// core by kCoreLift, and colours each part by its shade (renderer.cpp).
inline constexpr std::uint8_t kShirtShade = 68, kSleeveShade = 88, kTrousersShade = 48, kSkinShade = 140;
// A carried box (cardboard): held by the person, so part of the person layer.
inline constexpr std::uint8_t kBoxShade = 112;
inline constexpr int kCoreLift = 12;

struct Solid {
  std::vector<Eigen::Vector3d> points;
  std::uint8_t shade = 80;  // grey level of its clothing or skin
};

struct BodyPose {
  SpinePose spine;          // exactly what the solids are built around
  SegmentalMotion motion;   // what posed it
  std::vector<Solid> solids;
};

// Share of whole-trunk flexion taken by the pelvis (the spine takes the rest).
inline constexpr double kPelvisFlexionShare = 1.0 / 3.0;

// Where a chair fits a seated subject, in the subject's frame (X forwards,
// Y up, mm) before the heading's turn: the seat's surface under the thighs'
// undersides at the hips, its front edge behind the knees, its back behind
// the buttocks, and its half width beyond the hips.
struct ChairPlace {
  double seat_top_y = 0;
  double seat_back_x = 0, seat_front_x = 0;
  double seat_half_width = 0;
};

class BodyModel {
 public:
  // Per-joint factors come from the subject, else from `seed` (±20 %).
  BodyModel(Subject subject, SubjectPosture posture, std::uint32_t seed);

  const Subject& subject() const { return subject_; }
  SubjectPosture posture() const { return posture_; }
  const std::array<JointAngles, kJointCount>& joint_factors() const { return factors_; }
  const SpinePose& neutral() const { return neutral_; }

  // Without limbs, the rest pose the phantom has always drawn (and the
  // legs stay where the neutral pose puts them); with limbs, each joint
  // turned from rest and the legs carried by the sway (a step aside).
  BodyPose pose(const TrunkMotion& motion, const LimbMotion* limbs = nullptr) const;
  // The spine's segmental motion for a whole-trunk motion: the spine's part
  // spread over the joints, and the pelvis rotating about the hip joints.
  SegmentalMotion segmental_motion(const TrunkMotion& motion) const;
  // The chair under this subject seated in the neutral pose.
  ChairPlace chair_place() const;

 private:
  void add_trunk(const SpinePose& spine, std::vector<Solid>& out) const;
  void add_head_and_arms(const SpinePose& spine, std::vector<Solid>& out) const;
  void add_legs(std::vector<Solid>& out) const;
  // The articulated versions (limbs.cpp).
  void add_posed_head_and_arms(const SpinePose& spine, const LimbMotion& limbs, std::vector<Solid>& out) const;
  void add_posed_legs(const LimbMotion& limbs, const Eigen::Vector3d& sway, std::vector<Solid>& out) const;
  // Rest directions of one leg (side −1 left / +1 right): hip to knee, knee
  // to ankle, and the foot's two ends from the ankle.
  struct LegRest {
    Eigen::Vector3d thigh, shin, heel, toe;
  };
  LegRest leg_rest(double side) const;
  // Where one resting leg's joints are (world, mm): the one place the rest
  // legs are drawn from, for the held legs and the articulated ones alike.
  struct LegJoints {
    Eigen::Vector3d hip, knee, ankle;
  };
  LegJoints leg_joints(double side) const;
  Eigen::Vector3d hip_offset(double side) const;  // in the L5 frame, side −1 left / +1 right

  Subject subject_;
  SubjectPosture posture_;
  double scale_;  // subject height / reference height
  // Offsets of the landmarks a measured subject may give (subject.hpp),
  // generic ones scaled by height otherwise: hip joints below L5 (L5
  // frame), top of the shoulder ring and shoulder joints above T1.
  double hip_y_, shoulder_ring_y_, shoulder_joint_y_;
  std::array<JointAngles, kJointCount> factors_;
  std::array<JointAngles, kJointCount> shares_;  // each joint's share, renormalised
  SpinePose neutral_;
};

// The whole body turned about the world's vertical axis (through the
// origin) by `heading_deg`, counter-clockwise seen from above: the spine
// (the ground truth) and every solid. 180: the back to the frontal camera.
void turn(BodyPose& body, double heading_deg);

}  // namespace spinewatch::phantom
