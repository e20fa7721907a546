// The per-pair chain. Each stage lives in its own area (silhouette/, cvsm/,
// spine/, load/); this file only decides what flows where and when state
// is reset.
#include "spinewatch/estimator/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "silhouette/person_prior.hpp"
#include "spinewatch/estimator/anatomy/kinematics.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/load/ergonomics.hpp"
#include "spinewatch/estimator/load/schultz.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/estimator/spine/spine_dynamics.hpp"
#include "spinewatch/estimator/spine/spine_model.hpp"

namespace spinewatch {
namespace {

// The station's [silhouette] keys in the extractor's terms: times in
// seconds become frames at the camera rate.
SilhouetteOptions silhouette_options(const EstimatorOptions& o) {
  const SilhouetteConfig& c = o.silhouette;
  SilhouetteOptions s;
  s.background = c.background;
  s.learn_frames = c.learn_frames;
  s.threshold = c.threshold;
  s.min_blob_px = c.min_blob_px;
  s.chroma_threshold = c.chroma_threshold;
  s.shadow_ratio = c.shadow_ratio;
  const double fps = std::max(1.0, o.fps);
  s.adaptation.adapt_frames = c.adapt_s * fps;
  s.adaptation.margin_px = c.adapt_margin_px;
  s.adaptation.relearn_empty_frames = static_cast<int>(std::lround(c.relearn_empty_s * fps));
  s.bootstrap = c.bootstrap;
  s.bootstrapping.min_moved_px = c.min_blob_px;
  // The window spans three seconds of samples at the camera rate.
  s.bootstrapping.sample_every = std::max(1, static_cast<int>(std::lround(fps / 10)));
  return s;
}

// Why the last bootstrap attempt was refused, in the operator's words.
std::string bootstrap_stall_reason(const BootstrapAttempt& a, const BootstrapOptions& b, int threshold) {
  if (a.samples == 0) return "no frame has been sampled yet";
  if (a.moved_px < b.min_moved_px)
    return fmt::format("the subject has hardly moved ({} px changed, {} needed to see the scene behind them)", a.moved_px,
                       b.min_moved_px);
  const double limit = b.max_holdout_error * threshold;
  if (a.holdout_p90 > limit)
    return fmt::format("the scene is too cluttered to predict behind the subject (off by {:.0f} grey levels on scene "
                       "around them, at most {:.0f} allowed)",
                       a.holdout_p90, limit);
  if (a.holdout_outliers > b.max_holdout_outliers)
    return fmt::format("the subject reaches outside the region they swept ({:.1f} % of the scene around them differs)",
                       100 * a.holdout_outliers);
  return fmt::format("the subject has uncovered {:.0f} % of the scene behind them so far", 100 * a.revealed());
}

// The tracker's options: the [cvsm] keys, the worker and the placement of
// [subject], the models read.
CvsmOptions cvsm_options(const EstimatorOptions& o) {
  CvsmOptions c;
  c.subject_frames = o.cvsm.subject_frames;
  c.provisional_frames = o.cvsm.provisional_frames;
  c.lost_cost = o.cvsm.lost_cost;
  c.refine_steps = o.cvsm.refine_steps;
  c.limbs = o.cvsm.limbs;
  c.heading = o.cvsm.heading;
  c.height_mm = o.subject.height_mm;
  c.min_silhouette_px = o.silhouette.min_blob_px;
  c.spine_placement = o.subject.spine_placement;
  const KnownWorker worker = known_worker(o.subject);
  c.stature_mm = worker.stature_mm;
  c.c7_height_mm = worker.c7_height_mm;
  c.iliac_crest_height_mm = worker.iliac_crest_height_mm;
  c.mass_kg = worker.mass_kg;
  c.model = o.cvsm_model;
  c.spine = o.spine_model;
  return c;
}

// Frame interval for the dynamics: the pairs' spacing, bounded so that a
// stall or a duplicate timestamp cannot make a wild or a null step.
double step_seconds(std::optional<std::int64_t> previous_ns, std::int64_t now_ns) {
  if (!previous_ns) return 1.0 / 30;
  return std::clamp(double(now_ns - *previous_ns) * 1e-9, 1.0 / 240, 0.2);
}

// The ergonomic angles are the body's own (sagittal: the way the subject
// faces; docs/cvsm.md, "Heading"): measured on the posture turned back by
// the fit's heading, so a forward bend with the back to the frontal camera
// is a forward bend, not an extension.
SpinePose facing_front(const SpinePose& pose, double heading_deg) {
  if (heading_deg == 0) return pose;
  const Eigen::Matrix3d back = heading_rotation(-heading_deg);
  const Eigen::Quaterniond q_back(back);
  SpinePose turned = pose;
  for (VertebraPose& v : turned) {
    v.body_center = back * v.body_center;
    v.q = (q_back * v.q).normalized();
  }
  return turned;
}

}  // namespace

struct PostureEstimator::Impl {
  Impl(const CameraRig& r, const EstimatorOptions& o)
      : rig(r),
        options(o),
        silhouettes{SilhouetteExtractor(silhouette_options(o)), SilhouetteExtractor(silhouette_options(o))},
        tracker(r, cvsm_options(o)) {}

  // The stature the subject model stands on: given, the top of the head
  // standing (measured placement), or the height the fit chose (seated, or
  // the head above both pictures).
  std::optional<WorkerBody> worker_body() const {
    const KnownWorker given = known_worker(options.subject);
    const BodyModel* subject = tracker.subject_model();
    if (!given.stature_mm && !subject) return std::nullopt;
    WorkerBody b;
    b.rejected_stature_mm = tracker.rejected_stature_mm();
    // The landmarks place the spine with the measured placement, unless the
    // stature given with them was someone else's.
    if (options.subject.spine_placement == SpinePlacementMode::Measured && !(b.rejected_stature_mm && subject)) {
      b.c7_height_mm = given.c7_height_mm;
      b.iliac_crest_height_mm = given.iliac_crest_height_mm;
    }
    if (given.stature_mm && !(b.rejected_stature_mm && subject)) {
      b.stature_mm = *given.stature_mm;
      b.stature_source = BodyValueSource::Given;
    } else if (subject->shape.stature_measured) {
      b.stature_mm = subject->shape.stature_mm;
      b.stature_source = BodyValueSource::Measured;
    } else {
      b.stature_mm = subject->shape.stature_mm > 0 ? subject->shape.stature_mm : subject->shape.height_mm;
      b.stature_source = BodyValueSource::Estimated;
    }
    b.mass_kg = given.mass_kg.value_or(estimated_mass_kg(b.stature_mm));
    b.mass_source = given.mass_kg ? BodyValueSource::Given : BodyValueSource::Estimated;
    return b;
  }

  void set_worker(const KnownWorker& worker) {
    set_known_worker(options.subject, worker);
    tracker = CvsmTracker(rig, cvsm_options(options));
    drop_spine_model();
    for (Gate& g : gates) g.active = false;
  }

  // The accurate model, its dynamics and the ergonomics measured against
  // its neutral: built again (ensure_spine_model) from the next tracked fit.
  void drop_spine_model() {
    spine_model.reset();
    dynamics.reset();
    ergonomics.reset();
    dynamics_reset_pending = true;
    previous_t_ns.reset();
  }

  // Someone in view after the scene was empty for [cvsm] new_subject_after_s:
  // the station cannot tell who came back, and another person fitted with
  // the last one's model is confidently wrong (a taller man after a shorter
  // one: every posture 57–68 mm off; docs/cvsm.md, "Provisional model"). So
  // the subject model is built afresh, tracking again from its provisional
  // pairs; a shorter absence keeps it.
  void start_new_subject_after_empty_scene(SilhouetteStatus frontal, SilhouetteStatus lateral, std::int64_t t_ns) {
    auto someone = [](SilhouetteStatus s) {
      return s != SilhouetteStatus::NoPerson && s != SilhouetteStatus::LearningBackground &&
             s != SilhouetteStatus::NoBackground;
    };
    if (!someone(frontal) || !someone(lateral)) return;
    const double limit_s = options.cvsm.new_subject_after_s;
    if (last_person_ns && limit_s > 0 && double(t_ns - *last_person_ns) * 1e-9 >= limit_s && tracker.subject_model()) {
      spdlog::info("estimator: someone in view after {:.1f} s without anyone: the subject model is built afresh",
                   double(t_ns - *last_person_ns) * 1e-9);
      tracker.reset();
      drop_spine_model();
      for (Gate& g : gates) g.active = false;
    }
    last_person_ns = t_ns;
  }
  std::optional<std::int64_t> last_person_ns;  // the last pair with someone in both views

  // The frames' size is known with the first pair: then each view learns
  // where the subject can be, for bootstrapping a background.
  void ensure_person_priors(int width, int height) {
    if (priors_set) return;
    silhouettes[0].set_person_prior(person_prior(rig.frontal, width, height));
    silhouettes[1].set_person_prior(person_prior(rig.lateral, width, height));
    priors_set = true;
  }

  // The accurate model is built once the CVSM knows the subject's height.
  void ensure_spine_model() {
    if (dynamics) return;
    const BodyModel* subject = tracker.subject_model();
    const double height = subject ? subject->shape.height_mm : options.subject.height_mm;
    SpineModelOptions model_options;
    model_options.voxel_mm = options.spine.voxel_mm;
    // On the spine the CVSM placed in this subject: both models agree on
    // where T1 and L5 sit when the accurate one is driven to them.
    // Its neutral spine is the subject model's (the span between T1 and L5
    // the measured placement gave), set where the generic one stands.
    const SpineSpec& spine_spec = options.spine_model ? *options.spine_model : generic_spine_spec();
    SubjectSpine spine = subject_of_neutral(neutral_pose(spine_spec, height), height, spine_spec);
    if (subject) {
      SpinePose neutral = subject->neutral;
      const Eigen::Vector3d shift = spine[kWaistIndex].pose.body_center - neutral[kWaistIndex].body_center;
      for (auto& v : neutral) v.body_center += shift;
      spine = subject_of_neutral(neutral, height, spine_spec);
    }
    spine_model.emplace(SpineModel::from_subject(spine, model_options));
    DynamicsOptions dynamics_options;
    dynamics_options.substeps = options.spine.substeps;
    dynamics.emplace(*spine_model, dynamics_options);
    ergonomics.emplace(spine_model->neutral());
    load_params.height_mm = height;
    if (const auto body = worker_body()) load_params.body_mass_kg = body->mass_kg;
    if (spine_model_provisional) {
      spdlog::debug("estimator: provisional subject model: tracking while it is being built");
    } else if (const auto body = worker_body()) {
      spdlog::info("estimator: subject model built (stature {:.0f} mm {}, mass {:.1f} kg {})", body->stature_mm,
                   to_string(body->stature_source), body->mass_kg, to_string(body->mass_source));
      if (body->rejected_stature_mm)
        spdlog::warn(
            "estimator: the given stature {:.0f} mm is {:.0f} mm below the {:.0f} mm the cameras measure standing: not "
            "used (is the right worker set? [subject] stature_mm or the set_worker command)",
            *body->rejected_stature_mm, std::abs(*body->rejected_stature_mm - body->stature_mm), body->stature_mm);
    }
    if (subject)
      spdlog::debug("estimator: subject model: outline height {:.0f} mm, stature {:.0f} mm, neutral T1 {:.0f} mm, L5 {:.0f} mm",
                    subject->shape.height_mm, subject->shape.stature_mm, subject->neutral[kNeckIndex].body_center.y(),
                    subject->neutral[kWaistIndex].body_center.y());
  }

  // Logged once per change: the operator learns why there are no postures
  // and what to do, and learns when it is over.
  void report_background(SilhouetteStatus frontal, SilhouetteStatus lateral) {
    const bool none = frontal == SilhouetteStatus::NoBackground || lateral == SilhouetteStatus::NoBackground;
    if (none && !reported_no_background)
      spdlog::warn(
          "estimator: no background and the scene is not empty (someone in view): bootstrapping it from the "
          "subject's movement; postures stay \"init\" (flag no_background) until then. For a reliable start, "
          "capture the empty scene with `spinewatch background` and set silhouette.background_frontal/_lateral");
    for (int v = 0; v < 2; ++v) {
      const BackgroundSource source = silhouettes[v].background_model().source();
      if (source != reported_source[v] && source == BackgroundSource::Bootstrapped)
        spdlog::info("estimator: {} background bootstrapped with the subject in view", v == 0 ? "frontal" : "lateral");
      reported_source[v] = source;
    }
    reported_no_background = none;
    no_background_pairs = none ? no_background_pairs + 1 : 0;
    // Two whole bootstrap windows without a background: it is not coming
    // by itself (a cluttered room cannot be predicted behind the subject,
    // or the subject sits still). Said once, with why and what to do, so
    // a station is never silently `init` for ever.
    if (no_background_pairs == stalled_after_pairs()) {
      const int v = frontal == SilhouetteStatus::NoBackground ? 0 : 1;
      spdlog::warn("estimator: still no {} background after {} pairs: {}. Capture the empty scene with `spinewatch "
                   "background` and set silhouette.background_frontal/_lateral, or start the station with nobody in view",
                   v == 0 ? "frontal" : "lateral", no_background_pairs,
                   bootstrap_stall_reason(silhouettes[v].bootstrap_attempt(), silhouette_options(options).bootstrapping,
                                          options.silhouette.threshold));
    }
  }
  int stalled_after_pairs() const {
    const BootstrapOptions b = silhouette_options(options).bootstrapping;
    return 2 * b.window_samples * b.sample_every;
  }

  // While tracking, the next pair's person is looked for near where the
  // model is now: its outline grown by kGatePx, more than a fast bend
  // moves the outline in a frame (40 mm ≈ 6 px at the default rig).
  static constexpr int kGatePx = 16;
  void update_gates() {
    for (int v = 0; v < 2; ++v) {
      Gate& g = gates[v];
      g.fitted = last_fit.state == TrackingState::Tracking ? tracker.fitted_mask(kViews[v]) : BitMask{};
      g.active = !g.fitted.empty();
      if (!g.active) continue;
      if (g.mask.width() != g.fitted.width() || g.mask.height() != g.fitted.height())
        g.mask = BitMask(g.fitted.width(), g.fitted.height());
      dilate_square(g.fitted, kGatePx, g.mask);
    }
  }
  const BitMask* gate(int view) const { return gates[view].active ? &gates[view].mask : nullptr; }
  const BitMask* fitted(int view) const { return gates[view].active ? &gates[view].fitted : nullptr; }
  struct Gate {
    bool active = false;
    BitMask fitted;  // the model's outline of this pair
    BitMask mask;    // grown: where the next pair's person is looked for
  } gates[2];

  CameraRig rig;
  bool priors_set = false;
  EstimatorOptions options;
  bool reported_no_background = false;
  int no_background_pairs = 0;  // in a row
  BackgroundSource reported_source[2] = {BackgroundSource::None, BackgroundSource::None};
  SilhouetteExtractor silhouettes[2];
  CvsmTracker tracker;
  std::optional<SpineModel> spine_model;
  bool spine_model_provisional = false;  // built on a subject model still being built
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

void PostureEstimator::set_worker(const KnownWorker& worker) { impl_->set_worker(worker); }

bool PostureEstimator::relearn_background() {
  Impl& m = *impl_;
  bool relearning = false;
  for (SilhouetteExtractor& s : m.silhouettes) relearning = s.relearn_background() || relearning;
  if (!relearning) return false;
  // The fit's gates came from the old background's silhouettes.
  for (auto& g : m.gates) g.active = false;
  m.dynamics_reset_pending = true;
  m.previous_t_ns.reset();
  spdlog::info("estimator: background dropped on request; learning it again from the next frames");
  return true;
}

EstimatorTrace PostureEstimator::last_trace() const {
  const Impl& m = *impl_;
  EstimatorTrace trace;
  if (!m.processed) return trace;
  trace.silhouette[0] = &m.last_silhouettes[0].mask;
  trace.silhouette[1] = &m.last_silhouettes[1].mask;
  trace.fit = &m.last_fit;
  trace.body_model = m.tracker.subject_model();
  trace.background[0] = &m.silhouettes[0].background();
  trace.background[1] = &m.silhouettes[1].background();
  trace.background_source[0] = m.silhouettes[0].background_model().source();
  trace.background_source[1] = m.silhouettes[1].background_model().source();
  return trace;
}

Posture PostureEstimator::process(const FramePair& pair) {
  Impl& m = *impl_;
  Posture posture;
  posture.seq = pair.sequence;
  posture.t_ns = pair.timestamp_ns;

  m.ensure_person_priors(pair.frontal.luma().width, pair.frontal.luma().height);
  // Kept in Impl (moved, not copied) so that last_trace() can show them.
  m.last_silhouettes[0] = m.silhouettes[0].extract(pair.frontal.luma(), m.gate(0));
  m.last_silhouettes[1] = m.silhouettes[1].extract(pair.lateral.luma(), m.gate(1));
  const SilhouetteResult& frontal = m.last_silhouettes[0];
  const SilhouetteResult& lateral = m.last_silhouettes[1];
  m.start_new_subject_after_empty_scene(frontal.status, lateral.status, pair.timestamp_ns);
  m.last_fit = m.tracker.track(frontal, lateral);
  m.processed = true;
  m.update_gates();
  m.silhouettes[0].adapt(pair.frontal.luma(), m.fitted(0));
  m.silhouettes[1].adapt(pair.lateral.luma(), m.fitted(1));
  m.report_background(frontal.status, lateral.status);
  for (const SilhouetteExtractor& s : m.silhouettes) {
    const BackgroundCounters& c = s.background_model().counters();
    posture.background.updates += c.updates;
    posture.background.relearns += c.relearns;
    posture.background.bootstraps += c.bootstraps;
  }
  const CvsmResult& fit = m.last_fit;
  posture.state = fit.state;
  posture.fit = fit.fit;
  posture.worker = m.worker_body();

  if (fit.state == TrackingState::Lost) {
    m.dynamics_reset_pending = true;
    m.previous_t_ns.reset();
    return posture;
  }
  // Learning the background: no posture to give, not even a provisional one.
  if (!fit.estimated) return posture;
  // A provisional posture only from a fit that stands: beyond lost_cost the
  // model does not lie on the silhouettes (every init fit of the phantom
  // costs 0.21 at most; hands and a board whose trunk is in the background
  // cost 0.8–1.2), and the posture is null as a lost pair's would be
  // (docs/cvsm.md, "Real footage").
  if (fit.state == TrackingState::Init && fit.fit.cost > m.options.cvsm.lost_cost) return posture;
  posture.neck_dir = fit.neck_dir;
  posture.waist_dir = fit.waist_dir;
  if (fit.state == TrackingState::Init) {
    // Provisional (docs/interfaces.md §3): the CVSM's own estimate while the
    // subject's model is being built.
    posture.neck = fit.neck;
    posture.waist = fit.waist;
    posture.vertebrae = fit.vertebrae;
    return posture;
  }

  // A fit on the subject model still being built (docs/cvsm.md,
  // "Provisional model") drives an accurate model built on it; once the
  // subject model is complete, the accurate model and what rests on it are
  // built again from the complete one, as when nothing was provisional.
  if (m.dynamics && m.spine_model_provisional && !fit.provisional) m.drop_spine_model();
  if (!m.dynamics) m.spine_model_provisional = fit.provisional;
  m.ensure_spine_model();
  if (m.dynamics_reset_pending) {
    // Warm start from the CVSM's own vertebrae, then continue incrementally.
    m.dynamics->reset(fit.vertebrae);
    m.dynamics_reset_pending = false;
  }
  // The fit's end orientations carry its axial twist; the accurate model
  // spreads T1's twist against L5 over the levels by their torsion springs.
  const SpineTargets targets{fit.neck, fit.waist, fit.neck_dir, fit.waist_dir, fit.vertebrae[kNeckIndex].q,
                             fit.vertebrae[kWaistIndex].q};
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
  posture.ergonomics = m.ergonomics->update(facing_front(pose, fit.pose.heading), posture.loads, pair.timestamp_ns);
  return posture;
}

}  // namespace spinewatch
