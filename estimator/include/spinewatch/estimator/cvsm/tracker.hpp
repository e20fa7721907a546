#pragma once
// The CVSM fit (paper §3.1): a subject-specific model built from the first
// upright frames, then, per frame pair, a coarse-to-fine local search from
// the previous solution minimising the exclusive-or of the model's outline
// and both silhouettes; a global search (re)initialises when the cost says
// tracking is lost.
#include <memory>
#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/cvsm/heading_range.hpp"
#include "spinewatch/estimator/cvsm/limb_mode.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/frames/view.hpp"

namespace spinewatch {

// Mirrors the [cvsm] keys of the station configuration.
struct CvsmOptions {
  int subject_frames = 10;       // upright frames that build the subject's model
  // From this many of them on, the pose fitted against the model built so
  // far is published as tracking while the model is still being built
  // (docs/cvsm.md, "Provisional model"); ≥ subject_frames: only once built.
  int provisional_frames = 3;
  double lost_cost = 0.35;       // XOR / silhouette pixels above which tracking is lost
  double height_mm = 1750;       // used only when the head is cut off or the subject sits
  // The worker's stature when given (anatomy/worker.hpp): it replaces the
  // measured crown standing and the height search seated.
  std::optional<double> stature_mm;
  // The worker's measured C7 and iliac-crest heights when given: they place
  // T1 and L5 (measured placement only; anatomy/worker.hpp).
  std::optional<double> c7_height_mm, iliac_crest_height_mm;
  // The worker's mass when given: with the stature, the BMI the spine's
  // depth behind the back skin is placed for (anatomy/spine_depth.hpp).
  std::optional<double> mass_kg;
  std::optional<SubjectPosture> posture;  // nothing: decided from the first frames
  std::optional<CvsmSpec> model;          // nothing: the generic model built in
  std::optional<SpineSpec> spine;         // nothing: the generic spine built in
  // Where the spine sits in the measured body (config [subject] spine_placement).
  SpinePlacementMode spine_placement = SpinePlacementMode::Measured;
  int min_silhouette_px = 600;   // fewer pixels in a view: no person
  int local_budget = 16;         // cost evaluations per tracked frame
  // ... when the outline refinement follows (refine_steps > 0, fixed limbs): the
  // refinement settles the pose between the search's steps, so the search
  // tries the prediction and a few coarse steps only; half its budget or
  // a quarter fit as well (docs/cvsm.md, "Outline refinement"), and the
  // pair keeps within its CPU budget.
  int refined_local_budget = 4;
  int global_budget = 400;       // cost evaluations for a (re)initialisation
  // Tuning, not configuration: the searches (local and global) compare
  // candidates on every n-th row (a power of two) ...
  int search_row_step = 4;
  // ... and on the trunk outline through every n-th vertebra ring (T1 and
  // L5 always): the trunk is smooth, so the chords lose well under a pixel
  // and a candidate costs half. The reported fit uses every ring and row.
  int search_vertebra_step = 4;
  // Then, with refine_steps > 0 (config [cvsm] refine_steps), the pose
  // found is refined on the outline: that many Gauss–Newton steps pulling
  // the full model's outline ends on every n-th row to the silhouettes'
  // edges (docs/cvsm.md, "Outline refinement"). With auto limbs the
  // refined pose is published and the next pair is searched from the
  // searched one; with articulated limbs it has no effect.
  int refine_steps = 1;
  int refine_row_step = 2;
  LimbMode limbs = LimbMode::Auto;  // config [cvsm] limbs
  HeadingRange heading = HeadingRange::Front;  // config [cvsm] heading
  // Tuning, articulated limbs (and auto's arms): evaluations of the limbs' search per
  // tracked pair (the trunk held), then of the trunk's search again with
  // the limbs held (the joint refinement; 0: none).
  int limb_budget = 30;
  int joint_budget = 8;
};

struct CvsmResult {
  TrackingState state = TrackingState::Lost;  // init while building the subject model, tracking, lost
  Eigen::Vector3d neck = Eigen::Vector3d::Zero(), waist = Eigen::Vector3d::Zero();  // T1, L5 body centres, mm
  Eigen::Vector3d neck_dir = Eigen::Vector3d::UnitY(), waist_dir = Eigen::Vector3d::UnitY();
  SpinePose vertebrae{};  // the CVSM's own estimate of all 17
  FitDiagnostics fit;     // cost, xor/silhouette pixel counts per view, candidates, flag
  CvsmPose pose;          // the fitted deformation
  // Whether neck, waist and vertebrae hold a fit: not while the background
  // is learnt (state init) nor with no person (state lost).
  bool estimated = false;
  // Whether the subject model this fit used was still being built (fewer
  // than subject_frames pairs in it): published as tracking from
  // provisional_frames on, the model then completes from the next pairs.
  bool provisional = false;
  // When the fit settled on an axial twist of 6° or more: how many more
  // XOR pixels (on the search's rows) the mirrored twist scored. Below the
  // tracker's margin the sign is not resolved: fit.flag "twist_unresolved".
  std::optional<std::int64_t> twist_sign_margin_px;
  bool valid() const { return state != TrackingState::Lost; }
};

class CvsmTracker {
 public:
  CvsmTracker(const CameraRig& rig, CvsmOptions options);
  ~CvsmTracker();
  CvsmTracker(CvsmTracker&&) noexcept;
  CvsmTracker& operator=(CvsmTracker&&) noexcept;

  CvsmResult track(const BitMask& frontal, const BitMask& lateral);
  // Same, with the silhouette status of each view: no person → lost;
  // two blobs / occluded → the fit runs on the largest blob and is flagged.
  CvsmResult track(const SilhouetteResult& frontal, const SilhouetteResult& lateral);

  // The fitted model's outline in one view after the last track(); empty
  // when that frame was not tracking.
  BitMask fitted_mask(View view);
  // The subject model once built (during init: the current estimate).
  const BodyModel* subject_model() const;
  // The given stature (CvsmOptions::stature_mm) when the standing
  // silhouettes contradicted it and it was set aside (anatomy/worker.hpp,
  // kStatureMismatchMm); nothing otherwise.
  std::optional<double> rejected_stature_mm() const;
  // Starts over: a new subject.
  void reset();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinewatch
