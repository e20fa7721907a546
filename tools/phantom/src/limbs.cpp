// The articulated limbs and head (scenario.hpp's LimbMotion): each joint
// turned from the rest pose body.cpp draws, so a scenario without limbs
// and one whose limbs are all at rest draw the same person.
#include <cmath>

#include <Eigen/Geometry>

#include "solids.hpp"
#include "spinewatch/phantom/body.hpp"

namespace spinewatch::phantom {
namespace {

using detail::capsule;

Eigen::Matrix3d about(const Eigen::Vector3d& axis, double deg) {
  return Eigen::AngleAxisd(deg * kRadPerDeg, axis).toRotationMatrix();
}

// The head on the neck, in T1's frame: flexion about Z (nodding forwards,
// towards +X), lateral about X (towards the right, +Z), twist about Y.
Eigen::Quaterniond head_rotation(const HeadMotion& h) {
  const Eigen::Matrix3d r = about(Eigen::Vector3d::UnitY(), h.twist_deg) *
                            about(Eigen::Vector3d::UnitX(), h.lateral_deg) *
                            about(Eigen::Vector3d::UnitZ(), -h.flexion_deg);
  return Eigen::Quaterniond(r);
}

}  // namespace

void BodyModel::add_posed_head_and_arms(const SpinePose& spine, const LimbMotion& limbs, std::vector<Solid>& out) const {
  const Subject& s = subject_;
  const VertebraPose& t1 = spine[kNeckIndex];
  const Eigen::Quaterniond head_q = t1.q * head_rotation(limbs.head);
  const Eigen::Vector3d neck_base = t1.body_center + t1.q * Eigen::Vector3d(5 * scale_, 30 * scale_, 0);
  const Eigen::Vector3d neck_top = neck_base + head_q * Eigen::Vector3d(10 * scale_, s.neck_length_mm, 0);
  out.push_back(capsule(neck_base, neck_top, s.neck_radius_mm, s.neck_radius_mm, kSkinShade));
  Solid head{{}, kSkinShade};
  const Eigen::Vector3d centre = neck_top + head_q * Eigen::Vector3d(15 * scale_, 0.75 * s.head_half_height_mm, 0);
  for (const auto& u : detail::unit_sphere())
    head.points.push_back(centre + head_q * Eigen::Vector3d(s.head_half_depth_mm * u.x(), s.head_half_height_mm * u.y(),
                                                            s.head_half_width_mm * u.z()));
  out.push_back(std::move(head));

  // The arms go with the upper thorax (T3), as at rest.
  const Eigen::Quaterniond& thorax = spine[2].q;
  std::array<Eigen::Vector3d, 2> hands;
  for (int index = 0; index < 2; ++index) {
    const double side = index == 0 ? -1.0 : 1.0;
    const ArmMotion& arm = limbs.arms[std::size_t(index)];
    const Eigen::Vector3d shoulder =
        t1.body_center + thorax * Eigen::Vector3d(-s.spine_depth_thoracic_mm + 0.75 * s.chest.half_depth_mm,
                                                  shoulder_joint_y_, side * (0.5 * s.shoulder_width_mm - s.upper_arm_radius_mm));
    const Eigen::Vector3d upper_rest(0, -std::cos(7 * kRadPerDeg), side * std::sin(7 * kRadPerDeg));
    const Eigen::Vector3d fore_rest = (upper_rest + Eigen::Vector3d(0.35, 0, 0)).normalized();
    // The elbow bends in the plane of the rest bend; the upper arm rises
    // forwards (about Z), that plane swung out to the side (about Y).
    const Eigen::Vector3d elbow_axis = upper_rest.cross(fore_rest).normalized();
    const Eigen::Matrix3d raise =
        about(Eigen::Vector3d::UnitY(), -side * arm.swing_deg) * about(Eigen::Vector3d::UnitZ(), arm.elevation_deg);
    const Eigen::Vector3d upper_dir = raise * upper_rest;
    const Eigen::Vector3d fore_dir = raise * (about(elbow_axis, arm.elbow_deg) * fore_rest);
    const Eigen::Vector3d elbow = shoulder + thorax * (0.46 * s.arm_length_mm * upper_dir);
    const Eigen::Vector3d hand = elbow + thorax * (0.54 * s.arm_length_mm * fore_dir);
    hands[std::size_t(index)] = hand;
    out.push_back(capsule(shoulder, elbow, s.upper_arm_radius_mm, 0.85 * s.upper_arm_radius_mm, kSleeveShade));
    out.push_back(capsule(elbow, hand, s.forearm_radius_mm, 0.75 * s.forearm_radius_mm, kSleeveShade));
  }
  if (limbs.carries_box) {
    // Held between the palms, reaching back from the hands towards the chest.
    const Eigen::Matrix3d axes = thorax.toRotationMatrix();
    const double half_width = std::max(60.0, 0.5 * (hands[1] - hands[0]).norm() - 0.75 * s.forearm_radius_mm);
    const Eigen::Vector3d centre = 0.5 * (hands[0] + hands[1]) - axes * Eigen::Vector3d(110 * scale_, 0, 0);
    out.push_back(detail::box(centre, axes, Eigen::Vector3d(150 * scale_, 120 * scale_, half_width), kBoxShade));
  }
}

void BodyModel::add_posed_legs(const LimbMotion& limbs, const Eigen::Vector3d& sway, std::vector<Solid>& out) const {
  const Subject& s = subject_;
  const Eigen::Vector3d l5 = neutral_[kWaistIndex].body_center;
  for (int index = 0; index < 2; ++index) {
    const double side = index == 0 ? -1.0 : 1.0;
    const LegMotion& leg = limbs.legs[std::size_t(index)];
    const LegRest rest = leg_rest(side);
    const Eigen::Matrix3d hip_turn =
        about(Eigen::Vector3d::UnitX(), -side * leg.abduction_deg) * about(Eigen::Vector3d::UnitZ(), leg.flexion_deg);
    const Eigen::Matrix3d shin_turn = hip_turn * about(Eigen::Vector3d::UnitZ(), -leg.knee_deg);
    const Eigen::Vector3d hip = l5 + hip_offset(side) + sway;
    const Eigen::Vector3d knee = hip + hip_turn * rest.thigh;
    const Eigen::Vector3d ankle = knee + shin_turn * rest.shin;
    out.push_back(capsule(hip, knee, s.thigh_radius_mm, s.shin_radius_mm * 1.05, kTrousersShade));
    out.push_back(capsule(knee, ankle, s.shin_radius_mm, 0.6 * s.shin_radius_mm, kTrousersShade));
    out.push_back(capsule(ankle + shin_turn * rest.heel, ankle + shin_turn * rest.toe, 40 * scale_, 35 * scale_,
                          kTrousersShade));
  }
}

}  // namespace spinewatch::phantom
