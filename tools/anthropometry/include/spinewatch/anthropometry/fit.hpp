#pragma once
// Ordinary least squares on ANSUR II: the regressions of
// config/anthropometry.toml, their residuals on the training and the test
// subjects, and the stature-only baseline they are judged against
// (docs/anthropometry.md).
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/anatomy/linear_regression.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::anthropometry {

// What a frontal and a lateral silhouette of an upright person measure.
std::vector<std::string> silhouette_inputs();
// What the silhouettes do not show and the spine placement needs.
std::vector<std::string> spine_targets();

// The value of a named input or target for one subject: an ANSUR column,
// or `male` (1 / 0).
Result<double> input_value(const AnsurSubject& s, std::string_view name);

// Least squares of `target` on `inputs` with an intercept; residual_sd is
// the sample SD of the residuals on `subjects`.
Result<LinearRegression> fit_ols(const std::vector<AnsurSubject>& subjects, std::string_view target,
                                 const std::vector<std::string>& inputs);

// Residuals (measured − predicted) over a set of subjects.
struct ResidualStats {
  std::size_t n = 0;
  double mean = 0;
  double sd = 0;       // sample standard deviation
  double p95_abs = 0;  // 95th percentile of |residual|, nearest rank
  double max_abs = 0;
};
Result<ResidualStats> residuals(const LinearRegression& model, const std::vector<AnsurSubject>& subjects);

// One target's model, judged on both sets beside its baseline (the same
// target from stature alone, fitted on the same training subjects).
struct FittedTarget {
  LinearRegression model;
  LinearRegression baseline;
  ResidualStats train, test, baseline_train, baseline_test;
};

struct AnthropometryFit {
  std::size_t train_men = 0, train_women = 0, test_men = 0, test_women = 0;
  std::vector<FittedTarget> targets;  // per target: the sex-free model, then the one with sex
};

// Splits `subjects` (split.hpp), fits every target on the training set
// with and without sex, and scores each on both sets.
Result<AnthropometryFit> fit_anthropometry(const std::vector<AnsurSubject>& subjects);

// config/anthropometry.toml: the models with their figures, commented
// with the source and the command that made it.
std::string to_toml(const AnthropometryFit& fit);
// The residual table printed by the command.
std::string report(const AnthropometryFit& fit);

}  // namespace spinewatch::anthropometry
