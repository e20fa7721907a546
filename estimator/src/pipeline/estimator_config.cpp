// The estimator's configuration keys: one entry per key, beside nothing
// else. A new key: its member (with its default) in estimator_config.hpp,
// its entry here, its line in config/spinewatch.toml (docs/configuration.md).
#include "spinewatch/estimator/estimator_config.hpp"

namespace spinewatch {

const OptionTable<SilhouetteConfig>& SilhouetteConfig::keys() {
  using S = SilhouetteConfig;
  static const OptionTable<S> table = {
      mode_key("background", &S::background,
               {{"learn", BackgroundMode::Learn}, {"image", BackgroundMode::Image},
                {"threshold", BackgroundMode::Threshold}}),
      integer_key("learn_frames", &S::learn_frames, 1, 1000),
      integer_key("threshold", &S::threshold, 1, 254),
      integer_key("chroma_threshold", &S::chroma_threshold, 0, 255),
      number_key("shadow_ratio", &S::shadow_ratio, 0.0, 1.0),
      integer_key("min_blob_px", &S::min_blob_px, 1, 1000000),
      text_key("background_frontal", &S::background_frontal),
      text_key("background_lateral", &S::background_lateral),
      number_key("adapt_s", &S::adapt_s, 0.0, 3600.0),
      integer_key("adapt_margin_px", &S::adapt_margin_px, 0, 64),
      number_key("relearn_empty_s", &S::relearn_empty_s, 0.0, 86400.0),
      flag_key("bootstrap", &S::bootstrap),
  };
  return table;
}

const OptionTable<CvsmConfig>& CvsmConfig::keys() {
  using S = CvsmConfig;
  static const OptionTable<S> table = {
      text_key("model", &S::model),
      integer_key("subject_frames", &S::subject_frames, 0, 1000),
      integer_key("provisional_frames", &S::provisional_frames, 1, 1000),
      number_key("new_subject_after_s", &S::new_subject_after_s, 0.0, 86400.0),
      number_key("lost_cost", &S::lost_cost, 0.01, 2.0),
      integer_key("refine_steps", &S::refine_steps, 0, 4),
      mode_key("limbs", &S::limbs, {{"fixed", LimbMode::Fixed}, {"articulated", LimbMode::Articulated}, {"auto", LimbMode::Auto}}),
      mode_key("heading", &S::heading, {{"fixed", HeadingRange::Fixed}, {"front", HeadingRange::Front}, {"any", HeadingRange::Any}}),
  };
  return table;
}

const OptionTable<SpineConfig>& SpineConfig::keys() {
  using S = SpineConfig;
  static const OptionTable<S> table = {
      text_key("model", &S::model),
      number_key("voxel_mm", &S::voxel_mm, 0.25, 5.0),
      integer_key("substeps", &S::substeps, 1, 1000),
  };
  return table;
}

const OptionTable<SubjectConfig>& SubjectConfig::keys() {
  using S = SubjectConfig;
  // The worker's values are applied on reload (a new worker at the station).
  static const OptionTable<S> table = {
      measurement_key("stature_mm", &S::stature_mm, 1000.0, 2300.0).live(),
      measurement_key("mass_kg", &S::mass_kg, 20.0, 250.0).live(),
      measurement_key("c7_height_mm", &S::c7_height_mm, 800.0, 2000.0).live(),
      measurement_key("iliac_crest_height_mm", &S::iliac_crest_height_mm, 500.0, 1400.0).live(),
      number_key("height_mm", &S::height_mm, 1000.0, 2300.0),
      mode_key("spine_placement", &S::spine_placement,
               {{"measured", SpinePlacementMode::Measured}, {"generic", SpinePlacementMode::Generic}}),
  };
  return table;
}

KnownWorker known_worker(const SubjectConfig& s) {
  // 0 = not known, for every key of the worker.
  auto known = [](double v) { return v > 0 ? std::optional<double>(v) : std::nullopt; };
  return {known(s.stature_mm), known(s.mass_kg), known(s.c7_height_mm), known(s.iliac_crest_height_mm)};
}

void set_known_worker(SubjectConfig& s, const KnownWorker& w) {
  s.stature_mm = w.stature_mm.value_or(0);
  s.mass_kg = w.mass_kg.value_or(0);
  s.c7_height_mm = w.c7_height_mm.value_or(0);
  s.iliac_crest_height_mm = w.iliac_crest_height_mm.value_or(0);
}

}  // namespace spinewatch
