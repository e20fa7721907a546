#pragma once
// Deformation of the accurate spine model (paper §3.2, Eqs. 10–20):
// Newton–Euler rigid bodies under gravity, disc springs and the virtual end
// forces, integrated with linearly implicit (backward) Euler — stable at any
// step, see docs/spine-model.md.
#include <array>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "spinewatch/estimator/spine/spine_model.hpp"

namespace spinewatch {

struct SpineTargets {
  Eigen::Vector3d neck = Eigen::Vector3d::Zero(), waist = Eigen::Vector3d::Zero();  // T1 and L5 body centres, mm
  std::optional<Eigen::Vector3d> neck_dir, waist_dir;  // unit, T1 / L5 local +Y in world
  // Whole end orientations (T1 / L5), when the rough fit resolves the axial
  // twist: the end is then turned onto this one, its twist included, and
  // the torsion springs spread T1's twist against L5 over the levels. Its
  // +Y axis replaces neck_dir / waist_dir. Without one the end keeps the
  // twist it had at reset().
  std::optional<Eigen::Quaterniond> neck_q, waist_q;
};

struct DynamicsOptions {
  int substeps = 16;                 // implicit steps per step() call
  double frame_dt_s = 1.0 / 30;      // Δt of Eqs. 11–12 in settle()
  double end_tolerance_mm = 0.2;     // t_neck, t_waist of Eqs. 19–20
  double max_end_move_mm = 5.0;      // how far Eqs. 11–12 carry an end in one phase-1 step
  double max_end_turn_deg = 3.0;     // how far the end torques turn an end's target direction per phase 1
  double relax_tolerance_mm = 1e-3;  // phase 2 ends when no vertebra moves more than this a step
  int max_relax_steps = 12;          // implicit steps per phase 2 in settle()
  int max_iterations = 200;          // settle(): phase-1/phase-2 rounds before giving up
  // Virtual end torques toward neck_dir / waist_dir. The twist about those
  // directions is not observable from them, so an end keeps the twist it had
  // at reset() unless neck_q / waist_q give it; without a direction only
  // that twist is held.
  double direction_stiffness_nm_per_rad = 2000;
  bool gravity = true;
  // Scale on each joint's rotational spring (fit-spine writes these).
  std::array<double, kJointCount> bending_scale = filled_ones();

  static std::array<double, kJointCount> filled_ones() {
    std::array<double, kJointCount> a;
    a.fill(1.0);
    return a;
  }
};

// Eq. 10: the force one disc spring exerts on the upper vertebra, N, from
// its attachment points (mm, world) and the upper point's velocity relative
// to the lower one (m/s). Positive stretch pulls the upper vertebra down
// toward the lower; compression pushes it away.
Eigen::Vector3d disc_spring_force(const DiscSpring& spring, const Eigen::Vector3d& upper_point_mm,
                                  const Eigen::Vector3d& lower_point_mm,
                                  const Eigen::Vector3d& relative_velocity_m_s = Eigen::Vector3d::Zero());

struct SettleReport {
  int iterations = 0;       // phase-1/phase-2 rounds
  int implicit_steps = 0;
  double neck_error_mm = 0, waist_error_mm = 0;  // Eqs. 19–20 left-hand sides at the end
  bool converged = false;   // Eqs. 19–20 hold and the interior is at rest
};

class SpineDynamics {
 public:
  // Starts at rest in the model's neutral posture. `model` must outlive this.
  explicit SpineDynamics(const SpineModel& model, DynamicsOptions options = {});

  // Places the model in `pose` at rest (e.g. the CVSM's estimate on (re)initialisation).
  void reset(const SpinePose& pose);
  // One frame of `substeps` implicit steps of dt_s / substeps: the ends move
  // toward the targets (phase 1, Eq. 13, at most max_end_move_mm and
  // max_end_turn_deg a substep), then the remaining substeps relax the chain
  // with the ends held (phase 2, Eqs. 14–18). Continues from the previous state.
  SpinePose step(const SpineTargets& targets, double dt_s);
  // The paper's process repeated until Eqs. 19–20 hold and the interior has
  // stopped moving, or max_iterations.
  SettleReport settle(const SpineTargets& targets);

  const SpinePose& pose() const { return pose_; }
  const SpineModel& model() const { return *model_; }
  const DynamicsOptions& options() const { return options_; }

 private:
  const SpineModel* model_;
  DynamicsOptions options_;
  SpinePose pose_;
  SpinePose reference_;  // the pose at reset(): the end vertebrae keep its twist
  std::array<Eigen::Matrix<double, 6, 1>, kVertebraCount> velocity_;  // m/s and rad/s, world

  // One implicit step of size h; ends translate by end_move (m) and are
  // otherwise held. Returns the largest vertebra displacement, mm.
  double implicit_step(const SpineTargets& targets, double h, const Eigen::Vector3d& neck_move_m,
                       const Eigen::Vector3d& waist_move_m);
  // The targets of one phase 1: end positions at most max_end_move_mm and
  // directions at most max_end_turn_deg from where the ends are now.
  SpineTargets bounded_targets(const SpineTargets& targets) const;
};

}  // namespace spinewatch
