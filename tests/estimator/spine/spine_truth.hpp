#pragma once
// Ground truth for the spine tests, made with the kinematics the phantom
// renderer uses: a subject unlike the generic model (height, per-level
// spacings and sizes ±10 %, per-joint share of a bend ±20 %), posed by
// pose_spine(neutral, distribute(...) scaled per joint).
#include <cmath>
#include <vector>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/spine/subject.hpp"

namespace spinewatch::test {

struct TruthSubject {
  SubjectSpine spine;                          // neutral, as SUBJECT.json gives it
  std::array<double, kJointCount> joint_factor;  // share of a bend each joint takes, relative to distribute()
};

// Deterministic "random" factors in [1 − amplitude, 1 + amplitude].
inline double wobble(std::size_t i, double seed, double amplitude) {
  return 1.0 + amplitude * std::sin(2.399963 * double(i) * seed + seed);
}

inline TruthSubject make_subject(double height_mm, double seed) {
  SpineSpec spec = generic_spine_spec();
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    auto& v = spec.vertebrae[i];
    v.spacing_mm *= wobble(i, seed, 0.10);
    v.height_mm *= wobble(i + 40, seed, 0.10);
    v.width_mm *= wobble(i + 80, seed, 0.10);
    v.depth_mm *= wobble(i + 120, seed, 0.10);
  }
  TruthSubject s;
  const SpinePose neutral = neutral_pose(spec, height_mm, Eigen::Vector3d(10, 0.57 * height_mm, -5));
  const double scale = size_scale(spec, height_mm);
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    s.spine[i].pose = neutral[i];
    s.spine[i].dims = {spec.vertebrae[i].height_mm * scale, spec.vertebrae[i].width_mm * scale,
                       spec.vertebrae[i].depth_mm * scale};
  }
  for (std::size_t j = 0; j < kJointCount; ++j) s.joint_factor[j] = wobble(j + 200, seed, 0.20);
  return s;
}

inline Posture posture_of(const TruthSubject& s, const SegmentalMotion& m, std::uint64_t seq) {
  Posture p;
  p.seq = seq;
  p.t_ns = std::int64_t(seq) * 33'333'333;
  p.state = TrackingState::Tracking;
  p.vertebrae = pose_spine(neutral_of(s.spine), m);
  p.neck = (*p.vertebrae)[kNeckIndex].body_center;
  p.waist = (*p.vertebrae)[kWaistIndex].body_center;
  p.neck_dir = (*p.vertebrae)[kNeckIndex].q * Eigen::Vector3d::UnitY();
  p.waist_dir = (*p.vertebrae)[kWaistIndex].q * Eigen::Vector3d::UnitY();
  return p;
}

inline Posture truth_posture(const TruthSubject& s, double flexion_deg, double lateral_deg, double twist_deg,
                             std::uint64_t seq) {
  SegmentalMotion m = distribute(generic_spine_spec(), flexion_deg, lateral_deg, twist_deg);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    m.joints[j].flexion *= s.joint_factor[j];
    m.joints[j].lateral *= s.joint_factor[j];
    m.joints[j].twist *= s.joint_factor[j];
  }
  return posture_of(s, m, seq);
}

// Lateral bending 0 → +25° → −25° → 0, or flexion 0 → 50° → 0.
inline std::vector<Posture> lateral_sequence(const TruthSubject& s, int frames) {
  std::vector<Posture> out;
  for (int f = 0; f < frames; ++f)
    out.push_back(truth_posture(s, 0, 25.0 * std::sin(2 * M_PI * f / frames), 0, std::uint64_t(f)));
  return out;
}
inline std::vector<Posture> flexion_sequence(const TruthSubject& s, int frames) {
  std::vector<Posture> out;
  for (int f = 0; f < frames; ++f)
    out.push_back(truth_posture(s, 25.0 * (1 - std::cos(2 * M_PI * f / frames)), 0, 0, std::uint64_t(f)));
  return out;
}

}  // namespace spinewatch::test
