#include "spinewatch/estimator/anatomy/linear_regression.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/toml_fields.hpp"

namespace spinewatch {

bool LinearRegression::uses(std::string_view input) const {
  return std::find(inputs.begin(), inputs.end(), input) != inputs.end();
}

double LinearRegression::predict(std::span<const double> x) const {
  double y = intercept;
  for (std::size_t i = 0; i < coefficients.size() && i < x.size(); ++i) y += coefficients[i] * x[i];
  return y;
}

Result<double> LinearRegression::predict(const std::map<std::string, double, std::less<>>& values) const {
  double y = intercept;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    auto it = values.find(inputs[i]);
    if (it == values.end()) return Error{fmt::format("{}: input {} not given", target, inputs[i])};
    y += coefficients[i] * it->second;
  }
  return y;
}

const LinearRegression* AnthropometryModel::find(std::string_view target, bool with_sex) const {
  for (const LinearRegression& r : regressions)
    if (r.target == target && r.uses(kMaleInput) == with_sex) return &r;
  return nullptr;
}

const LinearRegression* AnthropometryModel::stature_only(std::string_view target) const {
  for (const LinearRegression& r : baselines)
    if (r.target == target) return &r;
  return nullptr;
}

namespace {

Result<std::vector<std::string>> string_array(const toml::table& t, std::string_view key, std::string_view source,
                                              std::string_view ctx) {
  const toml::array* a = t[key].as_array();
  if (!a) return Error{fmt::format("{}:{}: {}.{}: missing or not an array", source, t.source().begin.line, ctx, key)};
  std::vector<std::string> out;
  for (const toml::node& n : *a) {
    auto s = n.value<std::string>();
    if (!s) return Error{fmt::format("{}:{}: {}.{}: expected strings", source, n.source().begin.line, ctx, key)};
    out.push_back(*s);
  }
  return out;
}

Result<std::vector<double>> number_array(const toml::table& t, std::string_view key, std::string_view source,
                                         std::string_view ctx) {
  const toml::array* a = t[key].as_array();
  if (!a) return Error{fmt::format("{}:{}: {}.{}: missing or not an array", source, t.source().begin.line, ctx, key)};
  std::vector<double> out;
  for (const toml::node& n : *a) {
    auto v = n.value<double>();
    if (!n.is_number() || !v || !std::isfinite(*v))
      return Error{fmt::format("{}:{}: {}.{}: expected finite numbers", source, n.source().begin.line, ctx, key)};
    out.push_back(*v);
  }
  return out;
}

}  // namespace

Result<AnthropometryModel> parse_anthropometry(std::string_view text, std::string_view source) {
  auto parsed = detail::parse_toml(text, source);
  if (!parsed) return parsed.error();
  const toml::array* list = (*parsed)["regression"].as_array();
  if (!list || list->empty()) return Error{fmt::format("{}: [[regression]]: missing", source)};
  AnthropometryModel model;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const toml::table* t = (*list)[i].as_table();
    const std::string ctx = fmt::format("regression[{}]", i);
    if (!t) return Error{fmt::format("{}: {}: expected a table", source, ctx)};
    LinearRegression r;
    auto target = (*t)["target"].value<std::string>();
    if (!target || target->empty())
      return Error{fmt::format("{}:{}: {}.target: missing", source, t->source().begin.line, ctx)};
    r.target = *target;
    auto inputs = string_array(*t, "inputs", source, ctx);
    if (!inputs) return inputs.error();
    auto coefficients = number_array(*t, "coefficients", source, ctx);
    if (!coefficients) return coefficients.error();
    if (inputs->size() != coefficients->size())
      return Error{fmt::format("{}:{}: {}: {} inputs but {} coefficients", source, t->source().begin.line, ctx,
                               inputs->size(), coefficients->size())};
    r.inputs = std::move(inputs).value();
    r.coefficients = std::move(coefficients).value();
    if (auto s = detail::read_numbers(*t, source, ctx, {{"intercept", &r.intercept, -1e6, 1e6},
                                                        {"residual_sd", &r.residual_sd, 0, 1e6}});
        !s)
      return s.error();
    if (model.find(r.target, r.uses(kMaleInput)))
      return Error{fmt::format("{}:{}: {}: a second model of {} {} sex", source, t->source().begin.line, ctx, r.target,
                               r.uses(kMaleInput) ? "with" : "without")};
    // The stature-only baseline beside it: the same target from stature
    // alone (one per target; the sex-free and the with-sex model share it).
    if (const toml::table* b = (*t)["stature_only"].as_table(); b && !model.stature_only(r.target)) {
      LinearRegression base;
      base.target = r.target;
      base.inputs = {"stature"};
      base.coefficients = {0};
      const std::string bctx = ctx + ".stature_only";
      if (auto s = detail::read_numbers(*b, source, bctx, {{"intercept", &base.intercept, -1e6, 1e6},
                                                           {"stature", &base.coefficients[0], -10, 10},
                                                           {"train_sd", &base.residual_sd, 0, 1e6}});
          !s)
        return s.error();
      model.baselines.push_back(std::move(base));
    }
    model.regressions.push_back(std::move(r));
  }
  return model;
}

}  // namespace spinewatch
