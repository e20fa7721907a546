// The per-pair chain. Each stage lives in its own area (silhouette/, cvsm/,
// spine/, load/); this file only decides what flows where and when state
// is reset.
#include "spinewatch/estimator/pipeline.hpp"

#include <algorithm>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/spine_model.hpp"

namespace spinewatch {
namespace {

SilhouetteOptions silhouette_options(const EstimatorOptions& o) {
  SilhouetteOptions s;
  auto mode = parse_background_mode(o.background);
  // The configuration loader admits only valid names; a bad one here is a caller's bug.
  s.background = mode ? *mode : BackgroundMode::Learn;
  s.learn_frames = o.learn_frames;
  s.threshold = o.threshold;
  s.min_blob_px = o.min_blob_px;
  return s;
}

CvsmOptions cvsm_options(const EstimatorOptions& o) {
  CvsmOptions c;
  c.subject_frames = o.subject_frames;
  c.lost_cost = o.lost_cost;
  c.height_mm = o.height_mm;
  c.min_silhouette_px = o.min_blob_px;
  return c;
}

// Frame interval for the dynamics: the pairs' spacing, bounded so that a
// stall or a duplicate timestamp cannot make a wild or a null step.
double step_seconds(std::optional<std::int64_t> previous_ns, std::int64_t now_ns) {
  if (!previous_ns) return 1.0 / 30;
  return std::clamp(double(now_ns - *previous_ns) * 1e-9, 1.0 / 240, 0.2);
}

}  // namespace

struct PostureEstimator::Impl {
  Impl(const CameraRig& rig, const EstimatorOptions& o)
      : options(o),
        silhouettes{SilhouetteExtractor(silhouette_options(o)), SilhouetteExtractor(silhouette_options(o))},
        tracker(rig, cvsm_options(o)) {
    load_params.body_mass_kg = o.mass_kg;
  }

  // The accurate model is built once the CVSM knows the subject's height.
  void ensure_spine_model() {
    if (dynamics) return;
    const BodyModel* subject = tracker.subject_model();
    const double height = subject ? subject->shape.height_mm : options.height_mm;
    SpineModelOptions model_options;
    model_options.voxel_mm = options.voxel_mm;
    spine_model.emplace(SpineModel::generic(height, model_options));
    DynamicsOptions dynamics_options;
    dynamics_options.substeps = options.substeps;
    dynamics.emplace(*spine_model, dynamics_options);
    ergonomics.emplace(spine_model->neutral());
    load_params.height_mm = height;
    spdlog::info("estimator: subject model built (height {:.0f} mm)", height);
  }

  EstimatorOptions options;
  SilhouetteExtractor silhouettes[2];
  CvsmTracker tracker;
  std::optional<SpineModel> spine_model;
  std::optional<SpineDynamics> dynamics;
  bool dynamics_reset_pending = true;  // after start and after every lost pair
  std::optional<ErgonomicsMonitor> ergonomics;
  LoadParams load_params = default_load_params();
  std::optional<std::int64_t> previous_t_ns;
  SilhouetteResult last_silhouettes[2];
  CvsmResult last_fit;
  bool processed = false;
};

PostureEstimator::PostureEstimator(const CameraRig& rig, const EstimatorOptions& options)
    : impl_(std::make_unique<Impl>(rig, options)) {}

PostureEstimator::~PostureEstimator() = default;

Status PostureEstimator::set_backgrounds(const LumaView& frontal, const LumaView& lateral) {
  if (auto s = impl_->silhouettes[0].set_background(frontal); !s)
    return Error{fmt::format("frontal background: {}", s.error().message)};
  if (auto s = impl_->silhouettes[1].set_background(lateral); !s)
    return Error{fmt::format("lateral background: {}", s.error().message)};
  return Ok{};
}

EstimatorTrace PostureEstimator::last_trace() const {
  const Impl& m = *impl_;
  EstimatorTrace trace;
  if (!m.processed) return trace;
  trace.silhouette[0] = &m.last_silhouettes[0].mask;
  trace.silhouette[1] = &m.last_silhouettes[1].mask;
  trace.fit = &m.last_fit;
  trace.body_model = m.tracker.subject_model();
  return trace;
}

Posture PostureEstimator::process(const FramePair& pair) {
  Impl& m = *impl_;
  Posture posture;
  posture.seq = pair.sequence;
  posture.t_ns = pair.timestamp_ns;

  // Kept in Impl (moved, not copied) so that last_trace() can show them.
  m.last_silhouettes[0] = m.silhouettes[0].extract(pair.frontal.luma());
  m.last_silhouettes[1] = m.silhouettes[1].extract(pair.lateral.luma());
  const SilhouetteResult& frontal = m.last_silhouettes[0];
  const SilhouetteResult& lateral = m.last_silhouettes[1];
  m.last_fit = m.tracker.track(frontal, lateral);
  m.processed = true;
  const CvsmResult& fit = m.last_fit;
  posture.state = fit.state;
  posture.fit = fit.fit;

  if (fit.state == TrackingState::Lost) {
    m.dynamics_reset_pending = true;
    m.previous_t_ns.reset();
    return posture;
  }
  // Learning the background: no posture to give, not even a provisional one.
  if (!fit.estimated) return posture;
  posture.neck_dir = fit.neck_dir;
  posture.waist_dir = fit.waist_dir;
  if (fit.state == TrackingState::Init) {
    // Provisional (interfaces.md §3): the CVSM's own estimate while the
    // subject's model is being built.
    posture.neck = fit.neck;
    posture.waist = fit.waist;
    posture.vertebrae = fit.vertebrae;
    return posture;
  }

  m.ensure_spine_model();
  if (m.dynamics_reset_pending) {
    // Warm start from the CVSM's own vertebrae, then continue incrementally.
    m.dynamics->reset(fit.vertebrae);
    m.dynamics_reset_pending = false;
  }
  const SpineTargets targets{fit.neck, fit.waist, fit.neck_dir, fit.waist_dir};
  const SpinePose pose = m.dynamics->step(targets, step_seconds(m.previous_t_ns, pair.timestamp_ns));
  m.previous_t_ns = pair.timestamp_ns;

  posture.vertebrae = pose;
  posture.neck = pose[kNeckIndex].body_center;
  posture.waist = pose[kWaistIndex].body_center;
  const auto angles = intervertebral_angles(pose);
  for (std::size_t i = 0; i < kJointCount; ++i)
    posture.angles.push_back({fmt::format("{}-{}", kVertebraNames[i], kVertebraNames[i + 1]), angles[i].flexion,
                              angles[i].lateral, angles[i].twist});
  posture.loads = compute_loads(pose, m.load_params);
  posture.ergonomics = m.ergonomics->update(pose, posture.loads, pair.timestamp_ns);
  return posture;
}

}  // namespace spinewatch
