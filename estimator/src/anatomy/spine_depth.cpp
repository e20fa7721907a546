#include "spinewatch/estimator/anatomy/spine_depth.hpp"

#include <cmath>
#include <stdexcept>

#include "common/toml_fields.hpp"

namespace spinewatch {

SpineRegion region_of(std::size_t vertebra_index) {
  return vertebra_index >= 12 ? SpineRegion::Lumbar : SpineRegion::Thoracic;  // L1 is index 12
}

Result<SpineDepthRule> SpineDepthRule::parse(std::string_view text, std::string_view source) {
  auto parsed = detail::parse_toml(text, source);
  if (!parsed) return parsed.error();
  SpineDepthRule r;
  auto table = [&](std::string_view name) { return detail::toml_table(*parsed, name, source); };
  auto rule = table("rule");
  if (!rule) return rule.error();
  if (auto s = detail::read_numbers(**rule, source, "rule", {{"reference_bmi", &r.reference_bmi_, 15, 40}}); !s)
    return s.error();
  for (auto [name, out] : {std::pair{"thoracic", &r.thoracic_}, std::pair{"lumbar", &r.lumbar_}}) {
    auto t = table(name);
    if (!t) return t.error();
    if (auto s = detail::read_numbers(**t, source, name,
                                      {{"tissue_mm", &out->tissue.mean_mm, 0, 150},
                                       {"tissue_per_bmi", &out->tissue_per_bmi, 0, 5},
                                       {"tissue_sd_mm", &out->tissue.sd_mm, 0, 50},
                                       {"canal_mm", &out->canal.mean_mm, 0, 40},
                                       {"canal_sd_mm", &out->canal.sd_mm, 0, 20},
                                       {"half_body_mm", &out->half_body.mean_mm, 0, 40},
                                       {"half_body_sd_mm", &out->half_body.sd_mm, 0, 20}});
        !s)
      return s.error();
  }
  auto outline = table("outline_bmi");
  if (!outline) return outline.error();
  if (auto s = detail::read_numbers(**outline, source, "outline_bmi",
                                    {{"intercept", &r.outline_intercept_, -100, 100},
                                     {"waist_depth", &r.outline_waist_, -1, 1},
                                     {"stature", &r.outline_stature_, -1, 1},
                                     {"residual_sd", &r.outline_sd_, 0, 20}});
      !s)
    return s.error();
  auto placement = table("placement");
  if (!placement) return placement.error();
  if (auto s = detail::read_numbers(**placement, source, "placement",
                                    {{"t1_below_cervicale_sd_mm", &r.t1_sd_, 0, 50},
                                     {"l5_below_iliocristale_sd_mm", &r.l5_sd_, 0, 50},
                                     {"truncate_sd", &r.truncate_sd_, 0.5, 5}});
      !s)
    return s.error();
  return r;
}

double SpineDepthRule::mean_mm(SpineRegion region, double bmi) const {
  const RegionDepth& d = at(region);
  return d.tissue.mean_mm + d.tissue_per_bmi * (bmi - reference_bmi_) + d.canal.mean_mm + d.half_body.mean_mm;
}

double SpineDepthRule::bone_sd_mm(SpineRegion region) const {
  const RegionDepth& d = at(region);
  return std::hypot(d.canal.sd_mm, d.half_body.sd_mm);
}

double SpineDepthRule::sd_mm(SpineRegion region) const { return std::hypot(tissue_sd_mm(region), bone_sd_mm(region)); }

double SpineDepthRule::bmi_from_outline(double waist_depth_mm, double stature_mm) const {
  return outline_intercept_ + outline_waist_ * waist_depth_mm + outline_stature_ * stature_mm;
}

const SpineDepthRule& default_spine_depth() {
  static const SpineDepthRule rule = [] {
    auto parsed = SpineDepthRule::parse(embedded_spine_depth_toml(), "config/spine-depth.toml");
    if (!parsed) throw std::logic_error(parsed.error().message);
    return std::move(parsed).value();
  }();
  return rule;
}

}  // namespace spinewatch
