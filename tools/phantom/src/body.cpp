#include "spinewatch/phantom/body.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "solids.hpp"

namespace spinewatch::phantom {

namespace detail {

const std::vector<Eigen::Vector3d>& unit_sphere() {
  static const std::vector<Eigen::Vector3d> points = [] {
    std::vector<Eigen::Vector3d> p{Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY()};
    for (int lat = -60; lat <= 60; lat += 30)
      for (int lon = 0; lon < 360; lon += 30)
        p.emplace_back(std::cos(lat * kRadPerDeg) * std::cos(lon * kRadPerDeg), std::sin(lat * kRadPerDeg),
                       std::cos(lat * kRadPerDeg) * std::sin(lon * kRadPerDeg));
    return p;
  }();
  return points;
}

Solid capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra, double rb, std::uint8_t shade) {
  Solid s{{}, shade};
  for (const auto& u : unit_sphere()) {
    s.points.push_back(a + ra * u);
    s.points.push_back(b + rb * u);
  }
  return s;
}

Solid box(const Eigen::Vector3d& centre, const Eigen::Matrix3d& axes, const Eigen::Vector3d& half, std::uint8_t shade) {
  Solid s{{}, shade};
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d sign((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
    s.points.push_back(centre + axes * sign.cwiseProduct(half));
  }
  return s;
}

}  // namespace detail

namespace {

using detail::capsule;
using detail::unit_sphere;

constexpr int kRingPoints = 20;
constexpr std::size_t kT12 = 11, kL1 = 12;

// Clothing and skin, darker than the scene so the person stands out.
constexpr std::uint8_t kShirt = kShirtShade, kSleeve = kSleeveShade, kTrousers = kTrousersShade, kSkin = kSkinShade;

Section lerp(const Section& a, const Section& b, double t) {
  return {a.half_width_mm + t * (b.half_width_mm - a.half_width_mm), a.half_depth_mm + t * (b.half_depth_mm - a.half_depth_mm)};
}

// An elliptical ring in a vertebra's frame: `back` is where the back skin
// surface lies (local x), the ring reaches 2 × half_depth forward from it.
std::vector<Eigen::Vector3d> ring(const Eigen::Vector3d& origin, const Eigen::Quaterniond& q, double y, double back,
                                  const Section& s) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(kRingPoints);
  const double xc = back + s.half_depth_mm;
  for (int k = 0; k < kRingPoints; ++k) {
    const double a = 2.0 * M_PI * k / kRingPoints;
    points.push_back(origin + q * Eigen::Vector3d(xc + s.half_depth_mm * std::cos(a), y, s.half_width_mm * std::sin(a)));
  }
  return points;
}

}  // namespace

BodyModel::BodyModel(Subject subject, SubjectPosture posture, std::uint32_t seed)
    : subject_(std::move(subject)), posture_(posture) {
  const SpineSpec& spec = generic_spine_spec();
  scale_ = size_scale(spec, subject_.height_mm);
  if (subject_.joint_factors) {
    factors_ = *subject_.joint_factors;
  } else {
    std::seed_seq seq{seed, 0x5bd1e995u};  // a stream of its own: noise settings do not change the subject
    std::mt19937 rng(seq);
    std::uniform_real_distribution<double> factor(0.8, 1.2);
    for (auto& f : factors_) f = {factor(rng), factor(rng), factor(rng)};
  }
  const SegmentalMotion base = distribute(spec, 1.0, 1.0, 1.0);
  JointAngles sum;
  for (std::size_t i = 0; i < kJointCount; ++i) {
    shares_[i] = {base.joints[i].flexion * factors_[i].flexion, base.joints[i].lateral * factors_[i].lateral,
                  base.joints[i].twist * factors_[i].twist};
    sum.flexion += shares_[i].flexion;
    sum.lateral += shares_[i].lateral;
    sum.twist += shares_[i].twist;
  }
  for (auto& s : shares_) s = {s.flexion / sum.flexion, s.lateral / sum.lateral, s.twist / sum.twist};

  // Standing, L5 is where the subject's landmarks put it, else at the
  // generic fraction of height. Seated, the spine keeps its standing
  // length and the head its height above T1, so a measured sitting height
  // puts L5 at seat + sitting height − (stature − standing L5); without
  // one, L5 is about 0.11 × height above the seat (the ischial tuberosities
  // are ~9 cm below the hip joints).
  const double standing_l5 = subject_.l5_height_mm.value_or(spec.l5_height_fraction * subject_.height_mm);
  double l5_height = standing_l5;
  if (posture_ == SubjectPosture::Seated)
    l5_height = subject_.sitting_height_mm
                    ? subject_.seat_height_mm + *subject_.sitting_height_mm - subject_.height_mm + standing_l5
                    : subject_.seat_height_mm + 0.11 * subject_.height_mm;
  // The generic chain scaled so that it spans the subject's T1–L5 height
  // (its shape does not change with size, so the span is linear in the
  // scale); without landmarks it is scaled by stature, as the estimator's.
  double spine_size = subject_.height_mm;
  if (subject_.t1_height_mm && subject_.l5_height_mm) {
    const SpinePose reference = neutral_pose(spec, spec.reference_height_mm, Eigen::Vector3d::Zero());
    const double reference_span = reference[kNeckIndex].body_center.y() - reference[kWaistIndex].body_center.y();
    spine_size = spec.reference_height_mm * (*subject_.t1_height_mm - *subject_.l5_height_mm) / reference_span;
  }
  neutral_ = neutral_pose(spec, spine_size, Eigen::Vector3d(0, l5_height, 0));

  // Standing T1, for the shoulders (the neutral spine is upright).
  const double standing_t1 = neutral_[kNeckIndex].body_center.y() - l5_height + standing_l5;
  hip_y_ = subject_.hip_joint_height_mm ? *subject_.hip_joint_height_mm - standing_l5 : -100 * scale_;
  shoulder_ring_y_ = subject_.shoulder_height_mm ? *subject_.shoulder_height_mm - standing_t1 : 18 * scale_;
  // The shoulder joints 33 mm (scaled) below the ring's level, as generic.
  shoulder_joint_y_ = subject_.shoulder_height_mm ? shoulder_ring_y_ - 33 * scale_ : -15 * scale_;
}

Eigen::Vector3d BodyModel::hip_offset(double side) const {
  return {35 * scale_, hip_y_, side * 0.5 * subject_.hips.half_width_mm};
}

SegmentalMotion BodyModel::segmental_motion(const TrunkMotion& m) const {
  SegmentalMotion out;
  const double spine_flexion = m.flexion_deg * (1.0 - kPelvisFlexionShare);
  for (std::size_t i = 0; i < kJointCount; ++i)
    out.joints[i] = {shares_[i].flexion * spine_flexion, shares_[i].lateral * m.lateral_deg, shares_[i].twist * m.twist_deg};
  // The pelvis tilts about the hip joints, which stay put on the legs, so
  // L5 swings forward and down as it tilts.
  out.pelvis = {m.flexion_deg * kPelvisFlexionShare, 0, 0};
  const Eigen::Vector3d l5 = neutral_[kWaistIndex].body_center;
  const Eigen::Vector3d hips = l5 + hip_offset(0);
  out.pelvis_translation = hips + joint_rotation(out.pelvis) * (l5 - hips) - l5 + m.sway_mm;
  return out;
}

BodyPose BodyModel::pose(const TrunkMotion& m, const LimbMotion* limbs) const {
  BodyPose body;
  body.motion = segmental_motion(m);
  body.spine = pose_spine(neutral_, body.motion);
  if (!limbs) {
    add_legs(body.solids);
    add_trunk(body.spine, body.solids);
    add_head_and_arms(body.spine, body.solids);
    return body;
  }
  add_posed_legs(*limbs, m.sway_mm, body.solids);
  add_trunk(body.spine, body.solids);
  add_posed_head_and_arms(body.spine, *limbs, body.solids);
  return body;
}

void turn(BodyPose& body, double heading_deg) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(heading_deg * kRadPerDeg, Eigen::Vector3d::UnitY()));
  for (VertebraPose& v : body.spine) {
    v.body_center = q * v.body_center;
    v.q = (q * v.q).normalized();
  }
  for (Solid& solid : body.solids)
    for (Eigen::Vector3d& p : solid.points) p = q * p;
}

void BodyModel::add_trunk(const SpinePose& spine, std::vector<Solid>& out) const {
  const Subject& s = subject_;
  // Cross-sections at key levels, linearly interpolated between them.
  const Section upper_chest{s.chest.half_width_mm, 0.8 * s.chest.half_depth_mm};
  struct Key {
    std::size_t level;
    Section section;
  };
  const Key keys[] = {{0, upper_chest}, {4, s.chest}, {7, s.chest}, {kT12, lerp(s.chest, s.waist, 0.6)},
                      {14, s.waist}, {kWaistIndex, lerp(s.waist, s.hips, 0.5)}};
  auto section_at = [&](std::size_t level) {
    for (std::size_t k = 1; k < std::size(keys); ++k)
      if (level <= keys[k].level) {
        const double t = double(level - keys[k - 1].level) / double(keys[k].level - keys[k - 1].level);
        return lerp(keys[k - 1].section, keys[k].section, t);
      }
    return keys[std::size(keys) - 1].section;
  };

  // Rings from the bottom up: under the pelvis, the hips, L5 … T1, the
  // shoulders, the base of the neck.
  std::vector<std::vector<Eigen::Vector3d>> rings;
  std::vector<std::uint8_t> shades;
  const VertebraPose& l5 = spine[kWaistIndex];
  const double lumbar_back = -s.spine_depth_lumbar_mm;
  rings.push_back(ring(l5.body_center, l5.q, -190 * scale_, lumbar_back,
                       {0.88 * s.hips.half_width_mm, 0.92 * s.hips.half_depth_mm}));
  rings.push_back(ring(l5.body_center, l5.q, -95 * scale_, lumbar_back, s.hips));
  for (std::size_t i = kWaistIndex + 1; i-- > 0;) {
    const double depth = i >= kL1 ? s.spine_depth_lumbar_mm : s.spine_depth_thoracic_mm;
    rings.push_back(ring(spine[i].body_center, spine[i].q, 0, -depth, section_at(i)));
  }
  const VertebraPose& t1 = spine[kNeckIndex];
  const double thoracic_back = -s.spine_depth_thoracic_mm;
  rings.push_back(ring(t1.body_center, t1.q, shoulder_ring_y_, thoracic_back + 0.2 * s.chest.half_depth_mm,
                       {0.5 * s.shoulder_width_mm, 0.6 * s.chest.half_depth_mm}));
  rings.push_back(ring(t1.body_center, t1.q, 50 * scale_, -1.0 * s.neck_radius_mm,
                       {1.3 * s.neck_radius_mm, 1.2 * s.neck_radius_mm}));
  for (std::size_t k = 0; k + 1 < rings.size(); ++k) {
    Solid segment{rings[k], k < 3 ? kTrousers : kShirt};
    segment.points.insert(segment.points.end(), rings[k + 1].begin(), rings[k + 1].end());
    out.push_back(std::move(segment));
  }
}

void BodyModel::add_head_and_arms(const SpinePose& spine, std::vector<Solid>& out) const {
  const Subject& s = subject_;
  const VertebraPose& t1 = spine[kNeckIndex];
  const Eigen::Vector3d neck_base = t1.body_center + t1.q * Eigen::Vector3d(5 * scale_, 30 * scale_, 0);
  const Eigen::Vector3d neck_top = t1.body_center + t1.q * Eigen::Vector3d(15 * scale_, 30 * scale_ + s.neck_length_mm, 0);
  out.push_back(capsule(neck_base, neck_top, s.neck_radius_mm, s.neck_radius_mm, kSkin));

  Solid head{{}, kSkin};
  const Eigen::Vector3d centre = neck_top + t1.q * Eigen::Vector3d(15 * scale_, 0.75 * s.head_half_height_mm, 0);
  for (const auto& u : unit_sphere())
    head.points.push_back(centre + t1.q * Eigen::Vector3d(s.head_half_depth_mm * u.x(), s.head_half_height_mm * u.y(),
                                                          s.head_half_width_mm * u.z()));
  out.push_back(std::move(head));

  // The arms hang from the shoulders and go with the upper thorax (T3).
  const Eigen::Quaterniond& thorax = spine[2].q;
  for (double side : {-1.0, 1.0}) {
    const Eigen::Vector3d shoulder =
        t1.body_center + thorax * Eigen::Vector3d(-s.spine_depth_thoracic_mm + 0.75 * s.chest.half_depth_mm, shoulder_joint_y_,
                                                  side * (0.5 * s.shoulder_width_mm - s.upper_arm_radius_mm));
    // Slightly abducted (7°), elbow slightly bent.
    const Eigen::Vector3d upper_dir(0, -std::cos(7 * kRadPerDeg), side * std::sin(7 * kRadPerDeg));
    const Eigen::Vector3d fore_dir = (upper_dir + Eigen::Vector3d(0.35, 0, 0)).normalized();
    const Eigen::Vector3d elbow = shoulder + thorax * (0.46 * s.arm_length_mm * upper_dir);
    const Eigen::Vector3d hand = elbow + thorax * (0.54 * s.arm_length_mm * fore_dir);
    out.push_back(capsule(shoulder, elbow, s.upper_arm_radius_mm, 0.85 * s.upper_arm_radius_mm, kSleeve));
    out.push_back(capsule(elbow, hand, s.forearm_radius_mm, 0.75 * s.forearm_radius_mm, kSleeve));
  }
}

BodyModel::LegJoints BodyModel::leg_joints(double side) const {
  const Subject& s = subject_;
  const Eigen::Vector3d hip = neutral_[kWaistIndex].body_center + hip_offset(side);
  if (posture_ == SubjectPosture::Seated) {
    const Eigen::Vector3d knee = hip + Eigen::Vector3d(0.47 * s.leg_length_mm, -10 * scale_, 0);
    return {hip, knee, Eigen::Vector3d(knee.x() + 40 * scale_, 80 * scale_, knee.z())};
  }
  return {hip, Eigen::Vector3d(hip.x(), 0.5 * hip.y(), hip.z()), Eigen::Vector3d(hip.x(), 80 * scale_, hip.z())};
}

ChairPlace BodyModel::chair_place() const {
  const LegJoints j = leg_joints(1);
  ChairPlace c;
  // The thighs rest on the seat: it meets their undersides at the hips
  // (the pelvis's lowest ring sinks into it, as into a cushion). The front
  // edge stops short of the back of the knee, where a seat is set; the
  // seat is 450 mm deep for the reference adult, and runs back beyond the
  // buttocks to the backrest.
  c.seat_top_y = j.hip.y() - subject_.thigh_radius_mm;
  c.seat_front_x = j.knee.x() - 80 * scale_;
  c.seat_back_x = c.seat_front_x - 450 * scale_;
  c.seat_half_width = std::max(230.0, subject_.hips.half_width_mm + 40);
  return c;
}

BodyModel::LegRest BodyModel::leg_rest(double side) const {
  const LegJoints j = leg_joints(side);
  return {j.knee - j.hip, j.ankle - j.knee, Eigen::Vector3d(-20 * scale_, -40 * scale_, 0),
          Eigen::Vector3d(150 * scale_, -45 * scale_, 0)};
}

void BodyModel::add_legs(std::vector<Solid>& out) const {
  const Subject& s = subject_;
  for (double side : {-1.0, 1.0}) {
    const LegJoints j = leg_joints(side);
    const LegRest rest = leg_rest(side);
    out.push_back(capsule(j.hip, j.knee, s.thigh_radius_mm, s.shin_radius_mm * 1.05, kTrousers));
    out.push_back(capsule(j.knee, j.ankle, s.shin_radius_mm, 0.6 * s.shin_radius_mm, kTrousers));
    out.push_back(capsule(j.ankle + rest.heel, j.ankle + rest.toe, 40 * scale_, 35 * scale_, kTrousers));
  }
}

}  // namespace spinewatch::phantom
