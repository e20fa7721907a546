#pragma once
// Where the spine sits inside a body of a given stature: the T1 and L5
// body-centre heights of the upright neutral pose. The silhouettes show
// the stature, not the spine; measured adults (ANSUR II, the regressions
// of config/anthropometry.toml) tell where the skin landmarks of C7 and
// the iliac crest lie for that stature, and published skin-to-vertebra
// relations put T1 and L5 below them (docs/anthropometry.md). The phantom
// places a measured subject's spine from its own landmarks by the same
// relations; the estimator predicts them from what it sees.
#include <cstdint>
#include <optional>
#include <string_view>

#include "spinewatch/estimator/anatomy/linear_regression.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

enum class Sex : std::uint8_t { Male, Female };

// From the skin landmarks to the vertebral body centres.
struct SkinToVertebra {
  // T1 body centre below the C7 spinous process tip (cervicale): the tip
  // of the long, caudally sloping C7 process lies at about the level of
  // the C7/T1 disc, T1's centre a little below it.
  double t1_below_cervicale_mm = 15;
  // L5 body centre below the iliac-crest height (iliocristale): the
  // intercristal (Tuffier's) line crosses mostly the lower L4 body in men
  // and the upper L5 body in women (Snider et al. 2008), at L4/L5 pooled
  // (Kim et al. 2003).
  double l5_below_iliocristale_male_mm = 25;
  double l5_below_iliocristale_female_mm = 10;

  // Sex unknown (as it usually is at a station): halfway, so that neither
  // sex is favoured whatever the mix of a workplace (±7.5 mm either way).
  double l5_below_iliocristale_mm(std::optional<Sex> sex) const {
    if (!sex) return 0.5 * (l5_below_iliocristale_male_mm + l5_below_iliocristale_female_mm);
    return *sex == Sex::Male ? l5_below_iliocristale_male_mm : l5_below_iliocristale_female_mm;
  }
};

// How the estimator places the spine in the subject it measures.
enum class SpinePlacementMode : std::uint8_t {
  Measured,  // from measured adults: the regressions of config/anthropometry.toml
  Generic,   // the generic spine's fixed fractions of stature (config/spine-generic.toml)
};
// "measured" | "generic"; anything else is an error naming the accepted values.
Result<SpinePlacementMode> parse_spine_placement_mode(std::string_view text);

// T1 and L5 body-centre heights (mm) of the upright neutral pose.
struct SpinePlacement {
  double t1_mm = 0, l5_mm = 0;
};

class SpinePlacementModel {
 public:
  // From the stature-only regressions of cervicaleheight and
  // iliocristaleheight in `model` (what the subject model measures today
  // is the stature; the outline's other measurements are not yet read).
  static Result<SpinePlacementModel> from(const AnthropometryModel& model, const SkinToVertebra& rule = {});

  SpinePlacement predict(double stature_mm, std::optional<Sex> sex = std::nullopt) const;
  // Where skin landmarks were measured on this person (a known worker's
  // C7 and iliac-crest heights), each places its end of the spine by the
  // skin-to-vertebra rule; an end without one is predicted from the stature.
  SpinePlacement place(double stature_mm, std::optional<double> c7_height_mm,
                       std::optional<double> iliac_crest_height_mm, std::optional<Sex> sex = std::nullopt) const;
  const LinearRegression& cervicale() const { return cervicale_; }
  const LinearRegression& iliocristale() const { return iliocristale_; }

 private:
  LinearRegression cervicale_, iliocristale_;
  SkinToVertebra rule_;
};

// config/anthropometry.toml as built into the binary.
std::string_view embedded_anthropometry_toml();
// Its placement model (the embedded file is tested; a broken one throws).
const SpinePlacementModel& default_spine_placement();

// `spec` with its L5 height and T1–L5 span moved to `placement` for a
// subject of `height_mm`: the spacings are scaled (the curve's shape is
// kept) and l5_height_fraction set, so every user of the spec (the CVSM,
// the accurate model, the loads) sees the same placed spine.
SpineSpec placed_spine(const SpineSpec& spec, double height_mm, const SpinePlacement& placement);

}  // namespace spinewatch
