#include "spinewatch/daemon/estimator_options.hpp"

#include <fmt/format.h>

#include "spinewatch/frames/text_file.hpp"

namespace spinewatch {

EstimatorOptions estimator_options(const Config& c) {
  EstimatorOptions o;
  o.silhouette = c.silhouette;
  o.cvsm = c.cvsm;
  o.spine = c.spine;
  o.subject = c.subject;
  o.fps = c.cameras.fps;
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
