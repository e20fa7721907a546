#pragma once
// Linear predictions of what a silhouette does not show (the C7 and
// iliac-crest levels, hence T1 and L5) from what it does (stature, shoulder
// and hip heights, trunk breadths and depths). The coefficients are fitted
// on measured adults (ANSUR II) by `spinewatch fit-anthropometry` into
// config/anthropometry.toml (docs/anthropometry.md); this is only the
// arithmetic and the file's reading, no I/O.
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Input names are ANSUR II column names (lengths in mm), plus `male`: 1
// for a man, 0 for a woman, in the models that use sex.
inline constexpr std::string_view kMaleInput = "male";

// target = intercept + Σ coefficients[i] · inputs[i]
struct LinearRegression {
  std::string target;
  std::vector<std::string> inputs;
  std::vector<double> coefficients;  // one per input, same order
  double intercept = 0;
  double residual_sd = 0;  // of the fit on its own training subjects, target units

  bool uses(std::string_view input) const;
  // `x` in the order of `inputs` (same size).
  double predict(std::span<const double> x) const;
  // Inputs by name; a missing one is an error naming it and the target.
  Result<double> predict(const std::map<std::string, double, std::less<>>& values) const;
};

// The models of config/anthropometry.toml.
struct AnthropometryModel {
  std::vector<LinearRegression> regressions;
  // Each target's stature-only baseline ([regression.stature_only]).
  std::vector<LinearRegression> baselines;
  // The model for `target`, with or without sex as an input; nullptr when absent.
  const LinearRegression* find(std::string_view target, bool with_sex) const;
  // `target` from stature alone; nullptr when the file has no baseline for it.
  const LinearRegression* stature_only(std::string_view target) const;
};

// Reads the [[regression]] tables of an anthropometry file; `source`
// names it in errors ("config/anthropometry.toml:12: regression[0].intercept: missing").
Result<AnthropometryModel> parse_anthropometry(std::string_view toml_text, std::string_view source);

}  // namespace spinewatch
