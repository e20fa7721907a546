#pragma once
// The per-pair estimator: silhouettes → CVSM fit (neck, waist, end
// directions) → accurate spine model, warm-started from the previous pair →
// loads and ergonomic flags → one Posture. One instance per stream of pairs;
// not thread-safe (the daemon runs it on its estimator thread).
#include <cstdint>
#include <memory>
#include <vector>

#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/estimator/anatomy/worker.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/cvsm/limb_mode.hpp"
#include "spinewatch/estimator/estimator_config.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/frames/frame_pair.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

class BitMask;
struct BodyModel;
struct CvsmResult;

// What the last process() saw and fitted, for overlays and diagnostics.
// Valid until the next process(); null before the first one.
struct EstimatorTrace {
  const BitMask* silhouette[2] = {nullptr, nullptr};  // person blob, frontal and lateral
  const CvsmResult* fit = nullptr;
  const BodyModel* body_model = nullptr;  // the subject's CVSM; null until built
  // Each view's background as it stands after this pair (width × height
  // bytes; empty while there is none).
  const std::vector<std::uint8_t>* background[2] = {nullptr, nullptr};
  // Where each view's background came from (none while learning or bootstrapping).
  BackgroundSource background_source[2] = {BackgroundSource::None, BackgroundSource::None};
};

// What the estimator runs with: the station's [silhouette], [cvsm], [spine]
// and [subject] sections as they are (estimator_config.hpp holds their
// keys and defaults), the camera rate, and the models the caller read.
struct EstimatorOptions {
  SilhouetteConfig silhouette;
  CvsmConfig cvsm;
  SpineConfig spine;
  SubjectConfig subject;  // the worker (set_worker replaces it), the stature's guess, the spine's placement
  double fps = 30;        // the frame rate the silhouette's times are counted in ([cameras] fps)
  // The models of cvsm.model and spine.model: nothing = the generic ones
  // built in. The caller reads and parses the files (no I/O here).
  std::optional<CvsmSpec> cvsm_model;
  std::optional<SpineSpec> spine_model;
};

class PostureEstimator {
 public:
  PostureEstimator(const CameraRig& rig, const EstimatorOptions& options);
  ~PostureEstimator();
  PostureEstimator(const PostureEstimator&) = delete;
  PostureEstimator& operator=(const PostureEstimator&) = delete;

  // Everything but latency_us, which the caller measures end to end.
  Posture process(const FramePair& pair);

  // Stored empty-scene images for background = "image" (the caller reads
  // them; the estimator does no I/O). Errors name the view and the problem.
  Status set_backgrounds(const LumaView& frontal, const LumaView& lateral);

  // A new worker in view (the daemon's set_worker command): the subject
  // model and the accurate model are built again from the next upright
  // frames, with what is given of this one. The background is kept.
  void set_worker(const KnownWorker& worker);

  // Learns both views' backgrounds again from the next frames (an
  // operator's request, the daemon's live view): the tracking starts over
  // as at start (init, then tracking), the subject's model is kept. False
  // when the background is not learnt (silhouette.background = image or
  // threshold): nothing changes.
  bool relearn_background();

  EstimatorTrace last_trace() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
