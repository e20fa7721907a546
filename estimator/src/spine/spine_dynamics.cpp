// Deformation of the accurate spine model (paper §3.2).
//
// Integrator: linearly implicit (backward) Euler on the Newton–Euler
// equations of all 17 bodies at once,
//   (M/h² + C/h + K) Δ = F(x) + M v / h,   v⁺ = Δ / h,
// with K, C the Gauss–Newton stiffness and damping of the springs
// (Eq. 10) and joints at the current configuration. Backward Euler is stable
// for any h, so one frame interval needs only a few steps although the disc
// springs (≈ 10⁶ N/m on 10–60 g bodies) ring at several kHz: an explicit or
// symplectic scheme would need h < 2/ω ≈ 0.1 ms. Where h ≫ 1/ω (always, at
// frame rate) a step is a Newton step on the static equilibrium, which is
// what the paper's "iteration for converging oscillation" seeks. The chain
// couples neighbours only, so the 102×102 system is block tridiagonal and
// solves in O(17). Derivation and stability argument: docs/spine-model.md.
#include "spinewatch/estimator/spine/spine_dynamics.hpp"

#include <algorithm>
#include <cmath>

#include "spine/block_tridiagonal.hpp"
#include "spinewatch/estimator/units.hpp"

namespace spinewatch {
namespace {

using detail::Matrix6d;
using detail::Vector6d;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) {
  Eigen::Quaterniond p = q.normalized();
  if (p.w() < 0) p.coeffs() = -p.coeffs();
  const double s = p.vec().norm();
  if (s < 1e-12) return 2.0 * p.vec();
  return 2.0 * std::atan2(s, p.w()) * p.vec() / s;
}

Eigen::Vector3d bounded(const Eigen::Vector3d& v, double max_norm) {
  const double n = v.norm();
  return n > max_norm ? Eigen::Vector3d(v * (max_norm / n)) : v;
}

constexpr double kRotationReachMm = 20.0;   // converts a rotation step to a displacement at a vertebra's rim

}  // namespace

Eigen::Vector3d disc_spring_force(const DiscSpring& s, const Eigen::Vector3d& upper_mm, const Eigen::Vector3d& lower_mm,
                                  const Eigen::Vector3d& relative_velocity) {
  const Eigen::Vector3d d = (upper_mm - lower_mm) * 1e-3;
  const double len = d.norm();
  if (len < 1e-12) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d e = d / len;
  const double stretch = len - s.rest_length_mm * 1e-3;
  // Tension is softer than compression (spine-facts: ≈ 0.1×).
  const double k = (stretch < 0 ? s.k_compression_n_per_mm : s.k_tension_n_per_mm) * 1e3;
  // Eq. 10: T = −(l/|l|) [k (|l| − |l⁰|) + c (v · l/|l|)]. The paper's
  // damping term divides v·l by l·l, which is not a force; we use the
  // velocity along the spring, the usual dashpot.
  return -e * (k * stretch + s.damping_n_s_per_m * relative_velocity.dot(e));
}

SpineDynamics::SpineDynamics(const SpineModel& model, DynamicsOptions options)
    : model_(&model), options_(options) {
  reset(model.neutral());
}

void SpineDynamics::reset(const SpinePose& pose) {
  pose_ = pose;
  for (auto& v : pose_) v.q.normalize();
  reference_ = pose_;
  for (auto& v : velocity_) v.setZero();
}

double SpineDynamics::implicit_step(const SpineTargets& targets, double h, const Eigen::Vector3d& neck_move_m,
                                    const Eigen::Vector3d& waist_move_m) {
  detail::BlockTridiagonal<kVertebraCount> sys;
  sys.clear();
  std::array<Eigen::Vector3d, kVertebraCount> x;
  std::array<Eigen::Matrix3d, kVertebraCount> R;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    x[i] = pose_[i].body_center * 1e-3;
    R[i] = pose_[i].q.toRotationMatrix();
  }

  // Newton–Euler inertia about the body centre (the point Eqs. 14–17 hold),
  // from the particle mass properties (Eqs. 1–9), plus gravity f_g (Eq. 13/18).
  // Quadratic velocity terms (ω × Iω) are dropped: trunk rates below
  // ~2 rad/s make them < 10⁻⁴ of the joint moments.
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    const MassProperties& mp = model_->vertebra(i).mass;
    const double m = mp.mass_kg;
    const Eigen::Vector3d r = R[i] * (mp.com_mm * 1e-3);
    const Eigen::Matrix3d Ic = R[i] * (mp.inertia_kg_mm2 * 1e-6) * R[i].transpose();
    Matrix6d M;
    M.topLeftCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
    M.topRightCorner<3, 3>() = -m * skew(r);
    M.bottomLeftCorner<3, 3>() = m * skew(r);
    M.bottomRightCorner<3, 3>() = Ic - m * skew(r) * skew(r);
    sys.diag[i] += M / (h * h);
    sys.rhs[i] += M * velocity_[i] / h;
    if (options_.gravity) {
      const Eigen::Vector3d fg(0, -m * kGravity, 0);
      sys.rhs[i].head<3>() += fg;
      sys.rhs[i].tail<3>() += r.cross(fg);
    }
  }

  // f_disk: the Eq. 10 springs of each disc, and the joint's rotational spring.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t u = j, l = j + 1;
    const Disc& disc = model_->disc(j);
    for (const DiscSpring& s : disc.springs) {
      const Eigen::Vector3d ru = R[u] * (s.upper_local_mm * 1e-3), rl = R[l] * (s.lower_local_mm * 1e-3);
      const Eigen::Vector3d d = (x[u] + ru) - (x[l] + rl);
      const double len = d.norm();
      if (len < 1e-9) continue;
      const Eigen::Vector3d e = d / len;
      const bool compressed = len < s.rest_length_mm * 1e-3;
      const double k = (compressed ? s.k_compression_n_per_mm : s.k_tension_n_per_mm) * 1e3;
      Vector6d Ju, Jl;  // d|l| / d(translation, rotation) of each body
      Ju << e, ru.cross(e);
      Jl << -e, -rl.cross(e);
      // Eq. 10 elastic part explicit; its damping part enters implicitly (c/h below).
      const double force = disc_spring_force(s, (x[u] + ru) * 1e3, (x[l] + rl) * 1e3).dot(e);
      sys.rhs[u] += force * Ju;
      sys.rhs[l] += force * Jl;
      // Stiffness k and the damping term c of Eq. 10, implicit (c/h).
      const double kc = k + s.damping_n_s_per_m / h;
      sys.diag[u] += kc * Ju * Ju.transpose();
      sys.diag[l] += kc * Jl * Jl.transpose();
      sys.upper[j] += kc * Ju * Jl.transpose();
    }
    // Bending/torsion resistance about the lower vertebra's axes, inversely
    // proportional to the joint's range of motion (see spine_model.cpp).
    const Eigen::Quaterniond dev = pose_[l].q.conjugate() * pose_[u].q * disc.rest_relative.conjugate();
    const Eigen::Vector3d phi = rotation_vector(dev);
    const Eigen::Matrix3d K =
        R[l] * (options_.bending_scale[j] * disc.rotational_spring_nm_per_rad).asDiagonal() * R[l].transpose();
    const Eigen::Vector3d tau = -K * (R[l] * phi);
    sys.rhs[u].tail<3>() += tau;
    sys.rhs[l].tail<3>() -= tau;
    sys.diag[u].bottomRightCorner<3, 3>() += K;
    sys.diag[l].bottomRightCorner<3, 3>() += K;
    sys.upper[j].bottomRightCorner<3, 3>() -= K;
  }

  // Virtual torques turning the end vertebrae toward neck_dir / waist_dir
  // (our addition to Eqs. 11–12: the paper leaves the end orientations free,
  // which it names as a source of error). The goal is the reference
  // orientation swung onto the direction, so the end keeps its reference
  // twist; without a direction only that twist is held. Holding the twist
  // matters: with both ends free to spin about the line joining them, a
  // forward bend can buckle into a cheaper sideways one.
  // With a whole orientation (the fit's twist resolved) that is the goal.
  auto direction_torque = [&](std::size_t i, const std::optional<Eigen::Vector3d>& dir,
                              const std::optional<Eigen::Quaterniond>& q) {
    const double kd = options_.direction_stiffness_nm_per_rad;
    const Eigen::Vector3d ref_axis = reference_[i].q * Eigen::Vector3d::UnitY();
    const bool has_dir = q || (dir && dir->norm() > 1e-9);
    const Eigen::Vector3d goal_axis =
        q ? Eigen::Vector3d(*q * Eigen::Vector3d::UnitY()) : has_dir ? Eigen::Vector3d(dir->normalized()) : Eigen::Vector3d(R[i].col(1));
    const Eigen::Quaterniond goal =
        q ? q->normalized() : Eigen::Quaterniond::FromTwoVectors(ref_axis, goal_axis) * reference_[i].q;
    const Eigen::Vector3d error = rotation_vector(goal * pose_[i].q.conjugate());
    if (has_dir) {
      sys.rhs[i].tail<3>() += kd * error;
      sys.diag[i].bottomRightCorner<3, 3>() += kd * Eigen::Matrix3d::Identity();
    } else {
      const Eigen::Vector3d a = R[i].col(1);
      sys.rhs[i].tail<3>() += kd * a.dot(error) * a;
      sys.diag[i].bottomRightCorner<3, 3>() += kd * a * a.transpose();
    }
  };
  direction_torque(kNeckIndex, targets.neck_dir, targets.neck_q);
  direction_torque(kWaistIndex, targets.waist_dir, targets.waist_q);

  // The ends translate as prescribed: by the virtual forces' displacement in
  // phase 1 (Eqs. 11–13), not at all in phase 2 (Eqs. 14–17).
  for (int t = 0; t < 3; ++t) {
    sys.fix(kNeckIndex, t, neck_move_m[t]);
    sys.fix(kWaistIndex, t, waist_move_m[t]);
  }

  const std::array<Vector6d, kVertebraCount> delta = sys.solve();
  double largest_mm = 0;
  for (std::size_t i = 0; i < kVertebraCount; ++i) {
    if (!delta[i].allFinite()) {  // cannot happen with a positive definite system; keep the pose sane if it does
      velocity_[i].setZero();
      continue;
    }
    const Eigen::Vector3d dx = delta[i].head<3>(), dtheta = delta[i].tail<3>();
    pose_[i].body_center += dx * 1e3;
    const double angle = dtheta.norm();
    if (angle > 1e-15) pose_[i].q = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, dtheta / angle)) * pose_[i].q);
    pose_[i].q.normalize();
    velocity_[i] = delta[i] / h;
    largest_mm = std::max({largest_mm, dx.norm() * 1e3, angle * kRotationReachMm});
  }
  // Eqs. 15, 17: the held ends are at rest.
  velocity_[kNeckIndex].head<3>().setZero();
  velocity_[kWaistIndex].head<3>().setZero();
  return largest_mm;
}

SpineTargets SpineDynamics::bounded_targets(const SpineTargets& targets) const {
  // Large jumps are taken in pieces so that every implicit step stays close
  // to the equilibrium path (a single 50° swing can otherwise land the chain
  // in a buckled, twisted local minimum).
  SpineTargets t = targets;
  const double cap = options_.max_end_move_mm;
  t.neck = pose_[kNeckIndex].body_center + bounded(targets.neck - pose_[kNeckIndex].body_center, cap);
  t.waist = pose_[kWaistIndex].body_center + bounded(targets.waist - pose_[kWaistIndex].body_center, cap);
  const double turn = options_.max_end_turn_deg * M_PI / 180.0;
  auto turn_toward = [&](std::size_t i, std::optional<Eigen::Vector3d>& dir) {
    if (!dir || dir->norm() < 1e-9) return;
    const Eigen::Vector3d a = pose_[i].q * Eigen::Vector3d::UnitY(), b = dir->normalized();
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    if (angle <= turn) return;
    const Eigen::Quaterniond full = Eigen::Quaterniond::FromTwoVectors(a, b);
    dir = Eigen::Quaterniond::Identity().slerp(turn / angle, full) * a;
  };
  // A whole orientation is turned toward the same way, twist included;
  // its axis then stands for the direction.
  auto turn_orientation = [&](std::size_t i, std::optional<Eigen::Quaterniond>& q, std::optional<Eigen::Vector3d>& dir) {
    if (!q) return;
    Eigen::Quaterniond goal = q->normalized();
    if (goal.dot(pose_[i].q) < 0) goal.coeffs() *= -1;  // the short way round
    const double angle = pose_[i].q.angularDistance(goal);
    if (angle > turn) goal = pose_[i].q.slerp(turn / angle, goal);
    q = goal;
    dir = goal * Eigen::Vector3d::UnitY();
  };
  turn_toward(kNeckIndex, t.neck_dir);
  turn_toward(kWaistIndex, t.waist_dir);
  turn_orientation(kNeckIndex, t.neck_q, t.neck_dir);
  turn_orientation(kWaistIndex, t.waist_q, t.waist_dir);
  return t;
}

SpinePose SpineDynamics::step(const SpineTargets& targets, double dt_s) {
  const int n = std::max(1, options_.substeps);
  const double h = (dt_s > 0 ? dt_s : options_.frame_dt_s) / n;
  for (int i = 0; i < n; ++i) {
    // Phase 1 (Eq. 13) while the ends are away from the targets: f_neck and
    // f_waist of Eqs. 11–12, M (p − x′)/Δt², carry a free end from x′ to p in
    // Δt; we apply that displacement (bounded per substep) to the ends
    // directly rather than as a force the stiff discs would absorb. Once
    // there, phase 2 (Eqs. 14–18): ends held, the chain relaxes under
    // f_g + f_disk for the rest of the frame.
    const SpineTargets t = bounded_targets(targets);
    implicit_step(t, h, (t.neck - pose_[kNeckIndex].body_center) * 1e-3,
                  (t.waist - pose_[kWaistIndex].body_center) * 1e-3);
  }
  return pose_;
}

SettleReport SpineDynamics::settle(const SpineTargets& targets) {
  SettleReport report;
  const double h = options_.frame_dt_s;
  bool at_rest = false, clipped = true;
  for (;;) {
    report.neck_error_mm = (targets.neck - pose_[kNeckIndex].body_center).norm();
    report.waist_error_mm = (targets.waist - pose_[kWaistIndex].body_center).norm();
    // Eqs. 19–20, plus the interior having stopped moving.
    if (at_rest && !clipped && report.neck_error_mm < options_.end_tolerance_mm &&
        report.waist_error_mm < options_.end_tolerance_mm) {
      report.converged = true;
      break;
    }
    if (report.iterations >= options_.max_iterations) break;
    ++report.iterations;
    // Phase 1 (Eqs. 11–13).
    const SpineTargets t = bounded_targets(targets);
    clipped = t.neck_dir != targets.neck_dir || t.waist_dir != targets.waist_dir;
    double moved = implicit_step(t, h, (t.neck - pose_[kNeckIndex].body_center) * 1e-3,
                                 (t.waist - pose_[kWaistIndex].body_center) * 1e-3);
    ++report.implicit_steps;
    // Phase 2 (Eqs. 14–18) until the oscillation has died out.
    at_rest = false;
    for (int s = 0; s < options_.max_relax_steps && !at_rest; ++s) {
      moved = implicit_step(t, h, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
      ++report.implicit_steps;
      at_rest = moved < options_.relax_tolerance_mm;
    }
  }
  return report;
}

}  // namespace spinewatch
