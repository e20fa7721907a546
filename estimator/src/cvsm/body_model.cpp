#include "spinewatch/estimator/cvsm/body_model.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace spinewatch {
namespace {

// cos and sin of each control point's angle on its ring, k · 30°. A model
// is built for each candidate shape while a subject is refined, and these
// were a twentieth of a population sweep's CPU computed per point.
struct RingAngle {
  double cos, sin;
};
const std::array<RingAngle, kControlPoints>& unit_ring() {
  static const std::array<RingAngle, kControlPoints> ring = [] {
    std::array<RingAngle, kControlPoints> r{};
    for (int k = 0; k < kControlPoints; ++k) {
      const double a = k * (2.0 * M_PI / kControlPoints);
      r[static_cast<std::size_t>(k)] = {std::cos(a), std::sin(a)};
    }
    return r;
  }();
  return ring;
}

void add_ring_points(const ControlPlane& p, std::vector<Eigen::Vector3d>& out) {
  for (const auto& [c, s] : unit_ring()) {
    const double radial = c * (c > 0 ? p.front : p.back);
    // Component by component (the same sums as offset + local): a local
    // vector written as two scalars and read back as one packed pair
    // stalled the store forwarding, most of this function's time.
    const double local_x = p.axis_x ? 0.0 : radial, local_y = p.axis_x ? radial : 0.0;
    out.emplace_back(p.offset.x() + local_x, p.offset.y() + local_y, p.offset.z() + s * p.half_width);
  }
}

void mark_chain_planes(BodyModel& m) {
  m.in_chain.assign(m.planes.size(), 0);
  for (const auto& chain : m.chains)
    for (const int p : chain) m.in_chain[static_cast<std::size_t>(p)] = 1;
}

}  // namespace

BodyModel build_body_model(const CvsmSpec& spec, const SpineSpec& spine, const BodyShape& shape,
                           const Eigen::Vector3d& l5_center) {
  BodyModel m;
  m.shape = shape;
  const double H = shape.height_mm;
  m.neutral = neutral_pose(spine, H, l5_center);
  // Part heights are given for the upright pose; offsets are taken there.
  const SpinePose upright = neutral_pose(spine, H);

  // Built for each candidate shape while a subject's model is refined:
  // room for every part's plane and chain up front instead of growing.
  m.planes.reserve(spec.parts.size() + kVertebraCount);
  m.chains.reserve(7);  // trunk, two arms, two legs (two each seated)

  auto add = [&](const ControlPlane& p) {
    m.planes.push_back(p);
    return static_cast<int>(m.planes.size() - 1);
  };

  // Pelvis (listed top down, chained bottom up), trunk L5 → T1, head.
  std::vector<int> trunk_chain;
  trunk_chain.reserve(m.planes.capacity());
  std::vector<const CvsmSpec::Part*> pelvis;
  for (const auto& part : spec.parts)
    if (part.chain == "pelvis") pelvis.push_back(&part);
  auto part_plane = [&](const CvsmSpec::Part& part, double z_sign) {
    ControlPlane p;
    const bool limb = part.chain == "arm" || part.chain == "leg";
    const double girth = limb ? shape.limb_scale : 1.0;
    p.half_width = part.half_width * H * (limb ? girth : shape.width_scale);
    p.front = part.front * H * (limb ? girth : shape.depth_scale);
    p.back = part.back * H * (limb ? girth : shape.depth_scale);
    const double z = z_sign * part.z * H * (part.chain == "arm" ? shape.shoulder_scale : shape.width_scale);
    if (part.attach == "hip") {
      p.frame = z_sign < 0 ? kLegLeftFrame : kLegRightFrame;
      p.offset = Eigen::Vector3d(part.x * H, (part.y - spec.hip_y) * H, 0);
    } else {
      const std::size_t k = *vertebra_index(part.attach);
      p.frame = static_cast<int>(k);
      p.offset = Eigen::Vector3d(part.x * H, part.y * H - upright[k].body_center.y(), z);
      if (part.chain == "head") p.offset *= shape.head_scale;
    }
    return p;
  };
  for (auto it = pelvis.rbegin(); it != pelvis.rend(); ++it) trunk_chain.push_back(add(part_plane(**it, 1)));
  for (std::size_t i = kVertebraCount; i-- > 0;) {
    const CvsmSpec::Trunk& t = spec.trunk[i];
    const double depth = shape.measured_depth_mm[i] > 0 ? shape.measured_depth_mm[i] : t.depth * H * shape.depth_scale;
    ControlPlane p;
    p.frame = static_cast<int>(i);
    p.half_width = t.half_width * H * shape.width_scale;
    p.back = shape.spine_depth_mm[i] > 0 ? shape.spine_depth_mm[i] : t.spine_fraction * depth;
    // A rule-placed spine in a trunk the fit makes shallow keeps some body
    // in front of it (the vertebral body alone reaches ~20 mm forward).
    p.front = std::max(depth - p.back, std::max(25.0, 0.2 * depth));
    p.vertebra = true;
    trunk_chain.push_back(add(p));
  }
  for (const auto& part : spec.parts)
    if (part.chain == "shoulder") trunk_chain.push_back(add(part_plane(part, 1)));
  // The head turns on the neck about the centre of its lowest ring (the
  // neck's base); that ring stays with T1.
  int head_planes = 0;
  for (const auto& part : spec.parts)
    if (part.chain == "head") {
      ControlPlane p = part_plane(part, 1);
      if (head_planes++ == 0) {
        m.joints[static_cast<std::size_t>(JointId::Neck)] = {p.frame, p.offset, -1};
      } else {
        p.joint = static_cast<int>(JointId::Neck);
      }
      trunk_chain.push_back(add(p));
    }
  m.chains.push_back(std::move(trunk_chain));

  for (double side : {1.0, -1.0}) {
    std::vector<const CvsmSpec::Part*> arm_parts;
    for (const auto& part : spec.parts)
      if (part.chain == "arm") arm_parts.push_back(&part);
    const bool left = side < 0;
    const auto shoulder = static_cast<int>(left ? JointId::ShoulderLeft : JointId::ShoulderRight);
    const auto elbow = static_cast<int>(left ? JointId::ElbowLeft : JointId::ElbowRight);
    const auto hip = static_cast<int>(left ? JointId::HipLeft : JointId::HipRight);
    const auto knee_id = static_cast<int>(left ? JointId::KneeLeft : JointId::KneeRight);
    if (arm_parts.size() > 1) {  // one ring alone has no solid to fill
      // The shoulder joint's and the elbow's rings carry the upper arm,
      // the rest the forearm and hand; each turns about its ring's centre.
      std::vector<int> arm;
      for (std::size_t i = 0; i < arm_parts.size(); ++i) {
        ControlPlane p = part_plane(*arm_parts[i], side);
        if (i == 0) m.joints[static_cast<std::size_t>(shoulder)] = {p.frame, p.offset, -1};
        if (i == 1) m.joints[static_cast<std::size_t>(elbow)] = {p.frame, p.offset, shoulder};
        p.joint = i < 2 ? shoulder : elbow;
        arm.push_back(add(p));
      }
      m.chains.push_back(std::move(arm));
    }

    std::vector<const CvsmSpec::Part*> leg;
    for (const auto& part : spec.parts)
      if (part.chain == "leg") leg.push_back(&part);
    if (leg.size() < 2) continue;
    // The thigh turns about the hip joint (the leg frame's origin), the
    // shin about the knee ring's centre.
    const int leg_frame = left ? kLegLeftFrame : kLegRightFrame;
    m.joints[static_cast<std::size_t>(hip)] = {leg_frame, Eigen::Vector3d::Zero(), -1};
    if (shape.posture == SubjectPosture::Standing) {
      std::vector<int> chain;
      for (std::size_t i = 0; i < leg.size(); ++i) {
        ControlPlane p = part_plane(*leg[i], side);
        if (i == 1) m.joints[static_cast<std::size_t>(knee_id)] = {leg_frame, p.offset, hip};
        p.joint = i < 2 ? hip : knee_id;
        chain.push_back(add(p));
      }
      m.chains.push_back(std::move(chain));
    } else {
      // Seated: thigh forward and horizontal from the hip joint, shin down
      // from the knee to the ankle (the first, second and last leg planes).
      const double shin = (leg[1]->y - leg.back()->y) * H;
      ControlPlane top = part_plane(*leg.front(), side), knee = part_plane(*leg[1], side),
                   ankle = part_plane(*leg.back(), side);
      top.axis_x = true;
      top.offset = Eigen::Vector3d(0, 0, 0);
      ControlPlane knee_x = knee;
      knee_x.axis_x = true;
      knee_x.offset = Eigen::Vector3d(spec.thigh * H, 0, 0);
      knee.offset = knee_x.offset;
      ankle.offset = knee.offset + Eigen::Vector3d(0, -shin, 0);
      top.joint = knee_x.joint = hip;
      knee.joint = ankle.joint = knee_id;
      m.joints[static_cast<std::size_t>(knee_id)] = {leg_frame, knee.offset, hip};
      m.chains.push_back({add(top), add(knee_x)});
      m.chains.push_back({add(knee), add(ankle)});
    }
  }
  const Eigen::Vector3d hip(spec.hip_x * H, spec.hip_y * H - upright[kWaistIndex].body_center.y(), 0);
  const double hip_z = spec.hip_z * H * shape.width_scale;
  m.hip_right = hip + Eigen::Vector3d(0, 0, hip_z);
  m.hip_left = hip - Eigen::Vector3d(0, 0, hip_z);

  mark_chain_planes(m);
  m.local_points.reserve(m.planes.size() * kControlPoints);
  for (const auto& p : m.planes) add_ring_points(p, m.local_points);
  return m;
}

BodyModel thin_trunk(const BodyModel& model, int keep) {
  BodyModel thin = model;
  if (keep <= 1 || thin.chains.empty()) return thin;
  std::vector<int>& trunk = thin.chains.front();
  std::erase_if(trunk, [&](int p) {
    const ControlPlane& plane = model.planes[static_cast<std::size_t>(p)];
    return plane.vertebra && plane.frame != static_cast<int>(kWaistIndex) && plane.frame % keep != 0;
  });
  mark_chain_planes(thin);
  return thin;
}

SpinePose pose_vertebrae(const BodyModel& model, const SpineSpec& spine, const CvsmPose& pose) {
  SegmentalMotion motion = distribute(spine, pose.flexion, pose.lateral, pose.twist);
  motion.pelvis = {pose.pelvis_flexion, pose.pelvis_lateral, 0};
  // The pelvis tilts about the hip joints, which stay on the legs: L5
  // swings forward and down as it tilts. Tilt and translation then stay
  // independent parameters for the search (about L5, every tilt would need
  // a matching translation to keep the legs in place).
  const Eigen::Vector3d l5 = model.neutral[kWaistIndex].body_center;
  const Eigen::Vector3d hips = l5 + 0.5 * (model.hip_left + model.hip_right);  // neutral L5 frame is the world's
  motion.pelvis_translation = pose.translation + (hips + joint_rotation(motion.pelvis) * (l5 - hips) - l5);
  SpinePose posed = pose_spine(model.neutral, motion);
  if (pose.heading == 0) return posed;
  // The whole body turns about the vertical through the hip joints where
  // the translation put them: heading and translation stay independent.
  const Eigen::Matrix3d turn = heading_rotation(pose.heading);
  const Eigen::Quaterniond q_turn(turn);
  const Eigen::Vector3d pivot = hips + pose.translation;
  for (VertebraPose& v : posed) {
    v.body_center = pivot + turn * (v.body_center - pivot);
    v.q = (q_turn * v.q).normalized();
  }
  return posed;
}

Eigen::Matrix3d heading_rotation(double heading_deg) {
  return Eigen::AngleAxisd(heading_deg * (M_PI / 180), Eigen::Vector3d::UnitY()).toRotationMatrix();
}

bool LimbPose::neutral() const {
  for (const Side& s : side)
    if (s.shoulder_flexion != 0 || s.shoulder_abduction != 0 || s.elbow != 0 || s.hip_flexion != 0 ||
        s.hip_abduction != 0 || s.knee != 0)
      return false;
  return head_flexion == 0 && head_lateral == 0 && head_turn == 0;
}

Eigen::Matrix3d limb_joint_rotation(JointId joint, const LimbPose& limbs) {
  using Turn = Eigen::AngleAxisd;
  constexpr double kRad = M_PI / 180;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  const bool left = joint == JointId::ShoulderLeft || joint == JointId::ElbowLeft || joint == JointId::HipLeft ||
                    joint == JointId::KneeLeft;
  const LimbPose::Side& s = limbs.side[left ? 0 : 1];
  const double outward = left ? -1 : 1;  // the side's +Z: abduction turns about −X on the right, +X on the left
  switch (joint) {
    case JointId::ShoulderLeft:
    case JointId::ShoulderRight:
      return (Turn(s.shoulder_flexion * kRad, z) * Turn(-outward * s.shoulder_abduction * kRad, x)).toRotationMatrix();
    case JointId::ElbowLeft:
    case JointId::ElbowRight:
      return Turn(s.elbow * kRad, z).toRotationMatrix();
    case JointId::HipLeft:
    case JointId::HipRight:
      return (Turn(s.hip_flexion * kRad, z) * Turn(-outward * s.hip_abduction * kRad, x)).toRotationMatrix();
    case JointId::KneeLeft:
    case JointId::KneeRight:
      return Turn(-s.knee * kRad, z).toRotationMatrix();
    case JointId::Neck:
      return (Turn(-limbs.head_flexion * kRad, z) * Turn(limbs.head_lateral * kRad, x) * Turn(limbs.head_turn * kRad, y))
          .toRotationMatrix();
  }
  return Eigen::Matrix3d::Identity();
}

void control_points(const BodyModel& model, const SpinePose& v, std::vector<Eigen::Vector3d>& out, const LimbPose& limbs,
                    double heading_deg) {
  std::array<Eigen::Matrix3d, kFrameCount> R;
  std::array<Eigen::Vector3d, kFrameCount> c;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    R[i] = v[i].q.toRotationMatrix();
    c[i] = v[i].body_center;
  }
  R[kLegLeftFrame] = R[kLegRightFrame] = heading_deg == 0 ? Eigen::Matrix3d::Identity() : heading_rotation(heading_deg);
  c[kLegLeftFrame] = c[kWaistIndex] + R[kWaistIndex] * model.hip_left;
  c[kLegRightFrame] = c[kWaistIndex] + R[kWaistIndex] * model.hip_right;
  // Each joint's turn, its parents' included, as x → A·x + b in its
  // frame, then into the world: (R·A)·x + (c + R·b). Only joints that
  // turn (themselves or a parent): the others' planes are computed as
  // without articulation, bit for bit.
  std::array<Eigen::Matrix3d, kLimbJointCount> local_a, A;
  std::array<Eigen::Vector3d, kLimbJointCount> local_b, b;
  std::array<bool, kLimbJointCount> turned{};
  if (!limbs.neutral()) {
    for (std::size_t j = 0; j < kLimbJointCount; ++j) {  // parents come first in JointId
      const Joint& joint = model.joints[j];
      const Eigen::Matrix3d r = limb_joint_rotation(static_cast<JointId>(j), limbs);
      const bool own = !r.isIdentity(0);
      const bool parent = joint.parent >= 0 && turned[static_cast<std::size_t>(joint.parent)];
      if (!own && !parent) continue;
      Eigen::Matrix3d a = r;
      Eigen::Vector3d t = joint.pivot - r * joint.pivot;
      if (parent) {  // (a parent shares the child's frame)
        const auto p = static_cast<std::size_t>(joint.parent);
        t = local_a[p] * t + local_b[p];
        a = local_a[p] * a;
      }
      local_a[j] = a;
      local_b[j] = t;
      const auto f = static_cast<std::size_t>(joint.frame);
      A[j] = R[f] * a;
      b[j] = c[f] + R[f] * t;
      turned[j] = true;
    }
  }
  out.resize(model.local_points.size());
  for (std::size_t p = 0; p < model.planes.size(); ++p) {
    if (!model.in_chain[p]) continue;
    const ControlPlane& plane = model.planes[p];
    const auto f = static_cast<std::size_t>(plane.frame);
    if (plane.joint >= 0 && turned[static_cast<std::size_t>(plane.joint)]) {
      const auto j = static_cast<std::size_t>(plane.joint);
      for (std::size_t k = 0; k < kControlPoints; ++k) {
        const std::size_t i = p * kControlPoints + k;
        out[i] = b[j] + A[j] * model.local_points[i];
      }
      continue;
    }
    for (std::size_t k = 0; k < kControlPoints; ++k) {
      const std::size_t i = p * kControlPoints + k;
      out[i] = c[f] + R[f] * model.local_points[i];
    }
  }
}

}  // namespace spinewatch
