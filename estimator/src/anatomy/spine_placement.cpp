#include "spinewatch/estimator/anatomy/spine_placement.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace spinewatch {

Result<SpinePlacementMode> parse_spine_placement_mode(std::string_view text) {
  if (text == "measured") return SpinePlacementMode::Measured;
  if (text == "generic") return SpinePlacementMode::Generic;
  return Error{fmt::format("\"{}\": expected \"measured\" or \"generic\"", text)};
}

Result<SpinePlacementModel> SpinePlacementModel::from(const AnthropometryModel& model, const SkinToVertebra& rule) {
  SpinePlacementModel m;
  for (auto [target, out] : {std::pair{"cervicaleheight", &m.cervicale_}, std::pair{"iliocristaleheight", &m.iliocristale_}}) {
    const LinearRegression* r = model.stature_only(target);
    if (!r) return Error{fmt::format("anthropometry: no stature-only model of {}", target)};
    *out = *r;
  }
  m.rule_ = rule;
  return m;
}

SpinePlacement SpinePlacementModel::predict(double stature_mm, std::optional<Sex> sex) const {
  const double x[] = {stature_mm};
  return {cervicale_.predict(x) - rule_.t1_below_cervicale_mm,
          iliocristale_.predict(x) - rule_.l5_below_iliocristale_mm(sex)};
}

SpinePlacement SpinePlacementModel::place(double stature_mm, std::optional<double> c7_height_mm,
                                          std::optional<double> iliac_crest_height_mm, std::optional<Sex> sex) const {
  SpinePlacement p = predict(stature_mm, sex);
  if (c7_height_mm) p.t1_mm = *c7_height_mm - rule_.t1_below_cervicale_mm;
  if (iliac_crest_height_mm) p.l5_mm = *iliac_crest_height_mm - rule_.l5_below_iliocristale_mm(sex);
  return p;
}

const SpinePlacementModel& default_spine_placement() {
  static const SpinePlacementModel model = [] {
    auto parsed = parse_anthropometry(embedded_anthropometry_toml(), "config/anthropometry.toml");
    if (!parsed) throw std::logic_error(parsed.error().message);
    auto placement = SpinePlacementModel::from(*parsed);
    if (!placement) throw std::logic_error(placement.error().message);
    return std::move(placement).value();
  }();
  return model;
}

SpineSpec placed_spine(const SpineSpec& spec, double height_mm, const SpinePlacement& placement) {
  SpineSpec placed = spec;
  // The span of the spec's own neutral pose at this height; the shape of
  // the curve does not change with the spacings' common scale, so the
  // span scales linearly with it.
  const SpinePose neutral = neutral_pose(spec, height_mm, Eigen::Vector3d::Zero());
  const double span = neutral[kNeckIndex].body_center.y() - neutral[kWaistIndex].body_center.y();
  const double target = placement.t1_mm - placement.l5_mm;
  if (span > 0 && target > 0)
    for (auto& v : placed.vertebrae) v.spacing_mm *= target / span;
  if (height_mm > 0) placed.l5_height_fraction = placement.l5_mm / height_mm;
  return placed;
}

}  // namespace spinewatch
