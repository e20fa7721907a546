#include "spinewatch/estimator/cvsm/body_model.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch {
namespace {

void add_ring_points(const ControlPlane& p, std::vector<Eigen::Vector3d>& out) {
  for (int k = 0; k < kControlPoints; ++k) {
    const double a = k * (2.0 * M_PI / kControlPoints);
    const double c = std::cos(a), s = std::sin(a);
    const double radial = c * (c > 0 ? p.front : p.back);
    const Eigen::Vector3d local = p.axis_x ? Eigen::Vector3d(0, radial, s * p.half_width)
                                           : Eigen::Vector3d(radial, 0, s * p.half_width);
    out.push_back(p.offset + local);
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

  auto add = [&](const ControlPlane& p) {
    m.planes.push_back(p);
    return static_cast<int>(m.planes.size() - 1);
  };

  // Pelvis (listed top down, chained bottom up), trunk L5 → T1, head.
  std::vector<int> trunk_chain;
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
  for (const auto& part : spec.parts)
    if (part.chain == "head") trunk_chain.push_back(add(part_plane(part, 1)));
  m.chains.push_back(trunk_chain);

  for (double side : {1.0, -1.0}) {
    std::vector<const CvsmSpec::Part*> arm_parts;
    for (const auto& part : spec.parts)
      if (part.chain == "arm") arm_parts.push_back(&part);
    if (arm_parts.size() > 1) {  // one ring alone has no solid to fill
      std::vector<int> arm;
      for (const auto* part : arm_parts) arm.push_back(add(part_plane(*part, side)));
      m.chains.push_back(arm);
    }

    std::vector<const CvsmSpec::Part*> leg;
    for (const auto& part : spec.parts)
      if (part.chain == "leg") leg.push_back(&part);
    if (leg.size() < 2) continue;
    if (shape.posture == SubjectPosture::Standing) {
      std::vector<int> chain;
      for (const auto* part : leg) chain.push_back(add(part_plane(*part, side)));
      m.chains.push_back(chain);
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
  return pose_spine(model.neutral, motion);
}

void control_points(const BodyModel& model, const SpinePose& v, std::vector<Eigen::Vector3d>& out) {
  std::array<Eigen::Matrix3d, kFrameCount> R;
  std::array<Eigen::Vector3d, kFrameCount> c;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    R[i] = v[i].q.toRotationMatrix();
    c[i] = v[i].body_center;
  }
  R[kLegLeftFrame] = R[kLegRightFrame] = Eigen::Matrix3d::Identity();
  c[kLegLeftFrame] = c[kWaistIndex] + R[kWaistIndex] * model.hip_left;
  c[kLegRightFrame] = c[kWaistIndex] + R[kWaistIndex] * model.hip_right;
  out.resize(model.local_points.size());
  for (std::size_t p = 0; p < model.planes.size(); ++p) {
    if (!model.in_chain[p]) continue;
    const auto f = static_cast<std::size_t>(model.planes[p].frame);
    for (std::size_t k = 0; k < kControlPoints; ++k) {
      const std::size_t i = p * kControlPoints + k;
      out[i] = c[f] + R[f] * model.local_points[i];
    }
  }
}

}  // namespace spinewatch
