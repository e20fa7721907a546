#pragma once
// How deep the spine lies in front of the back skin: one published rule
// (config/spine-depth.toml, docs/anthropometry.md) — the soft tissue over
// the spinous processes, which grows with BMI, plus the bone from the
// spinal canal to the body centre, which does not. The estimator uses the
// rule's mean; the phantom draws measured subjects from its distribution,
// so the population sweep includes the rule's own uncertainty.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

enum class SpineRegion : std::uint8_t { Thoracic, Lumbar };
// T1…T12 thoracic, L1…L5 lumbar (vertebra index 0…16).
SpineRegion region_of(std::size_t vertebra_index);

struct DepthTerm {
  double mean_mm = 0, sd_mm = 0;
};

struct RegionDepth {
  DepthTerm tissue;             // skin to the spinal canal's posterior wall, at the reference BMI
  double tissue_per_bmi = 0;    // mm per kg/m²
  DepthTerm canal, half_body;   // bone: canal depth, half the body's depth
};

class SpineDepthRule {
 public:
  static Result<SpineDepthRule> parse(std::string_view toml_text, std::string_view source);

  // Body-centre depth in front of the back skin (mm) for a person of this BMI.
  double mean_mm(SpineRegion region, double bmi) const;
  // 1 SD between people of one BMI: the three terms in quadrature.
  double sd_mm(SpineRegion region) const;
  // The tissue's and the bone's parts of that SD (the phantom draws them apart).
  double tissue_sd_mm(SpineRegion region) const { return at(region).tissue.sd_mm; }
  double bone_sd_mm(SpineRegion region) const;

  // The BMI a trunk of this waist depth and stature implies (no mass given).
  double bmi_from_outline(double waist_depth_mm, double stature_mm) const;
  double outline_bmi_sd() const { return outline_sd_; }

  // Spread of the skin-to-vertebra offsets (their means: SkinToVertebra).
  double t1_below_cervicale_sd_mm() const { return t1_sd_; }
  double l5_below_iliocristale_sd_mm() const { return l5_sd_; }
  double truncate_sd() const { return truncate_sd_; }
  double reference_bmi() const { return reference_bmi_; }

 private:
  const RegionDepth& at(SpineRegion r) const { return r == SpineRegion::Thoracic ? thoracic_ : lumbar_; }
  double reference_bmi_ = 25;
  RegionDepth thoracic_, lumbar_;
  double outline_intercept_ = 0, outline_waist_ = 0, outline_stature_ = 0, outline_sd_ = 0;
  double t1_sd_ = 0, l5_sd_ = 0, truncate_sd_ = 2;
};

// config/spine-depth.toml as built into the binary.
std::string_view embedded_spine_depth_toml();
// Its rule (the embedded file is tested; a broken one throws).
const SpineDepthRule& default_spine_depth();

}  // namespace spinewatch
