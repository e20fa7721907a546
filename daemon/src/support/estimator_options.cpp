#include "spinewatch/daemon/estimator_options.hpp"

#include <fmt/format.h>

#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {

EstimatorOptions estimator_options(const Config& c) {
  EstimatorOptions o;
  o.background = c.silhouette.background;
  o.learn_frames = c.silhouette.learn_frames;
  o.threshold = c.silhouette.threshold;
  o.min_blob_px = c.silhouette.min_blob_px;
  o.chroma_threshold = c.silhouette.chroma_threshold;
  o.shadow_ratio = c.silhouette.shadow_ratio;
  o.adapt_s = c.silhouette.adapt_s;
  o.adapt_margin_px = c.silhouette.adapt_margin_px;
  o.relearn_empty_s = c.silhouette.relearn_empty_s;
  o.bootstrap = c.silhouette.bootstrap;
  o.fps = c.cameras.fps;
  o.subject_frames = c.cvsm.subject_frames;
  o.lost_cost = c.cvsm.lost_cost;
  o.refine_steps = c.cvsm.refine_steps;
  o.limbs = c.cvsm.limbs;
  o.substeps = c.spine.substeps;
  o.voxel_mm = c.spine.voxel_mm;
  o.worker = known_worker(c.subject);
  o.height_mm = c.subject.height_mm;
  o.spine_placement = c.subject.spine_placement;
  return o;
}

namespace {

// A model file named by `key`, parsed by `parse` (which names the file).
template <class Parse>
auto load_model(const std::string& key, const std::string& path, Parse parse)
    -> decltype(parse(std::string_view{}, std::string_view{})) {
  auto text = read_text_file(path);
  if (!text) return Error{fmt::format("{}: {}", key, text.error().message)};
  auto parsed = parse(*text, path);
  if (!parsed) return Error{fmt::format("{}: {}", key, parsed.error().message)};
  return parsed;
}

}  // namespace

Result<EstimatorOptions> load_estimator_options(const Config& c) {
  EstimatorOptions o = estimator_options(c);
  if (!c.cvsm.model.empty()) {
    auto model = load_model("cvsm.model", c.cvsm.model, parse_cvsm_spec);
    if (!model) return model.error();
    o.cvsm_model = std::move(model).value();
  }
  if (!c.spine.model.empty()) {
    auto model = load_model("spine.model", c.spine.model, parse_spine_spec);
    if (!model) return model.error();
    o.spine_model = std::move(model).value();
  }
  return o;
}

}  // namespace spinewatch
