#pragma once
// The estimator's sections of the station configuration ([silhouette],
// [cvsm], [spine], [subject]; config/spinewatch.toml documents each key):
// the values, their defaults, and each section's key table. The estimator
// reads these as they are (EstimatorOptions holds them); the daemon's
// configuration aggregates them.
#include <string>

#include "spinewatch/estimator/anatomy/spine_placement.hpp"
#include "spinewatch/estimator/anatomy/worker.hpp"
#include "spinewatch/estimator/cvsm/heading_range.hpp"
#include "spinewatch/estimator/cvsm/limb_mode.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/frames/option_table.hpp"

namespace spinewatch {

struct SilhouetteConfig {
  BackgroundMode background = BackgroundMode::Learn;
  int learn_frames = 10;
  int threshold = 28;         // grey levels above the background difference
  int chroma_threshold = 12;  // chroma levels that make a pixel person whatever its luma (YUYV); 0 = luma only
  double shadow_ratio = 0.5;  // darker down to this fraction, same colour: shadow, not person; 1 = keep shadows
  int min_blob_px = 600;
  // The station's empty scene (spinewatch background); "" = none. The
  // caller reads the images (PostureEstimator::set_backgrounds).
  std::string background_frontal = "";
  std::string background_lateral = "";
  double adapt_s = 2.0;         // time constant of the background's adaptation outside the person; 0 = off
  int adapt_margin_px = 8;      // pixels around the person the adaptation leaves alone
  double relearn_empty_s = 10;  // an empty scene this long re-learns the whole background; 0 = never
  bool bootstrap = true;        // no background and someone in view: bootstrap one from their movement
  bool operator==(const SilhouetteConfig&) const = default;
  static const OptionTable<SilhouetteConfig>& keys();
};

struct CvsmConfig {
  // "" = the generic model built in (config/cvsm-generic.toml); the caller
  // reads and parses the file (EstimatorOptions::cvsm_model).
  std::string model = "";
  int subject_frames = 10;           // upright frames used to build the subject's model
  int provisional_frames = 3;        // of them, after which its fit is published as tracking (docs/cvsm.md, "Provisional model")
  double new_subject_after_s = 2;    // someone in view after an empty scene this long: a new subject model; 0 = never
  double lost_cost = 0.35;           // cost above which tracking is lost
  int refine_steps = 1;              // outline refinement of each fit: Gauss–Newton steps, 0 = off
  LimbMode limbs = LimbMode::Auto;   // "auto", "fixed" or "articulated" (docs/cvsm.md, "Articulated limbs", "Arms where the views show them")
  HeadingRange heading = HeadingRange::Front;  // "fixed", "front" or "any" (docs/cvsm.md, "Heading")
  bool operator==(const CvsmConfig&) const = default;
  static const OptionTable<CvsmConfig>& keys();
};

struct SpineConfig {
  std::string model = "";  // "" = the generic model built in (EstimatorOptions::spine_model)
  double voxel_mm = 1.0;
  int substeps = 16;
  bool operator==(const SpineConfig&) const = default;
  static const OptionTable<SpineConfig>& keys();
};

struct SubjectConfig {
  // The worker's, when known (0 = not known: the stature measured or
  // estimated from the silhouettes, the mass estimated from the stature).
  double stature_mm = 0;
  double mass_kg = 0;
  // Skin landmarks measured on the worker at set-up (0 = not known): they
  // place T1 and L5 (docs/anthropometry.md, "A known worker").
  double c7_height_mm = 0;
  double iliac_crest_height_mm = 0;
  double height_mm = 1750.0;  // the starting guess where the stature is not seen
  // Where the spine sits in the measured body: "measured" (regressions on
  // ANSUR II, docs/anthropometry.md) or "generic" (fixed fractions of height).
  SpinePlacementMode spine_placement = SpinePlacementMode::Measured;
  bool operator==(const SubjectConfig&) const = default;
  static const OptionTable<SubjectConfig>& keys();
};

// The worker the [subject] keys describe (0 = not known).
KnownWorker known_worker(const SubjectConfig& subject);
// The [subject] keys of a worker (what is not known: 0); the other keys kept.
void set_known_worker(SubjectConfig& subject, const KnownWorker& worker);

}  // namespace spinewatch
