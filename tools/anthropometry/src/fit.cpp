#include "spinewatch/anthropometry/fit.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "spinewatch/anthropometry/split.hpp"

namespace spinewatch::anthropometry {

std::vector<std::string> silhouette_inputs() {
  // Heights of the top of the head, the shoulders, the hips and the crotch
  // (frontal outline), widths across shoulders, chest, waist and hips
  // (frontal), depths of chest, waist and buttocks (lateral).
  return {"stature",          "acromialheight", "trochanterionheight", "crotchheight", "biacromialbreadth",
          "bideltoidbreadth", "chestbreadth",   "waistbreadth",        "hipbreadth",   "chestdepth",
          "waistdepth",       "buttockdepth"};
}

std::vector<std::string> spine_targets() { return {"cervicaleheight", "iliocristaleheight"}; }

Result<double> input_value(const AnsurSubject& s, std::string_view name) {
  if (name == kMaleInput) return s.sex == Sex::Male ? 1.0 : 0.0;
  if (auto v = measurement(s, name)) return *v;
  return Error{fmt::format("{}: not an ANSUR measurement the reader keeps", name)};
}

namespace {

Result<Eigen::VectorXd> column_of(const std::vector<AnsurSubject>& subjects, std::string_view name) {
  Eigen::VectorXd out(Eigen::Index(subjects.size()));
  for (std::size_t i = 0; i < subjects.size(); ++i) {
    auto v = input_value(subjects[i], name);
    if (!v) return v.error();
    out[Eigen::Index(i)] = *v;
  }
  return out;
}

}  // namespace

Result<LinearRegression> fit_ols(const std::vector<AnsurSubject>& subjects, std::string_view target,
                                 const std::vector<std::string>& inputs) {
  const auto n = Eigen::Index(subjects.size());
  const auto p = Eigen::Index(inputs.size());
  if (n <= p + 1) return Error{fmt::format("{}: {} subjects cannot fit {} inputs", target, n, p)};
  Eigen::MatrixXd x(n, p + 1);
  x.col(0).setOnes();
  for (Eigen::Index j = 0; j < p; ++j) {
    auto column = column_of(subjects, inputs[std::size_t(j)]);
    if (!column) return column.error();
    x.col(j + 1) = *column;
  }
  auto y = column_of(subjects, target);
  if (!y) return y.error();
  // Column-pivoting QR: the breadths and heights are strongly collinear
  // (all grow with body size), where the normal equations lose digits.
  const auto qr = x.colPivHouseholderQr();
  if (qr.rank() < p + 1) return Error{fmt::format("{}: the inputs are linearly dependent on these subjects", target)};
  const Eigen::VectorXd beta = qr.solve(*y);

  LinearRegression r;
  r.target = std::string(target);
  r.inputs = inputs;
  r.intercept = beta[0];
  for (Eigen::Index j = 0; j < p; ++j) r.coefficients.push_back(beta[j + 1]);
  const Eigen::VectorXd e = *y - x * beta;
  r.residual_sd = std::sqrt(e.squaredNorm() / double(n - 1));  // mean is 0 with an intercept
  return r;
}

Result<ResidualStats> residuals(const LinearRegression& model, const std::vector<AnsurSubject>& subjects) {
  if (subjects.empty()) return Error{fmt::format("{}: no subjects to score", model.target)};
  std::vector<double> e, x(model.inputs.size());
  for (const AnsurSubject& s : subjects) {
    for (std::size_t j = 0; j < x.size(); ++j) {
      auto v = input_value(s, model.inputs[j]);
      if (!v) return v.error();
      x[j] = *v;
    }
    auto y = input_value(s, model.target);
    if (!y) return y.error();
    e.push_back(*y - model.predict(x));
  }
  ResidualStats st;
  st.n = e.size();
  for (double v : e) st.mean += v;
  st.mean /= double(e.size());
  double ss = 0;
  for (double v : e) ss += (v - st.mean) * (v - st.mean);
  st.sd = e.size() > 1 ? std::sqrt(ss / double(e.size() - 1)) : 0;
  std::vector<double> a;
  for (double v : e) a.push_back(std::abs(v));
  std::sort(a.begin(), a.end());
  // Nearest rank: the smallest value with at least 95 % of |e| at or below it.
  const auto rank = std::size_t(std::ceil(0.95 * double(a.size())));
  st.p95_abs = a[std::max<std::size_t>(rank, 1) - 1];
  st.max_abs = a.back();
  return st;
}

Result<AnthropometryFit> fit_anthropometry(const std::vector<AnsurSubject>& subjects) {
  AnthropometryFit fit;
  const std::vector<AnsurSubject> train = subjects_in(subjects, Partition::Train);
  const std::vector<AnsurSubject> test = subjects_in(subjects, Partition::Test);
  for (const AnsurSubject& s : train) (s.sex == Sex::Male ? fit.train_men : fit.train_women)++;
  for (const AnsurSubject& s : test) (s.sex == Sex::Male ? fit.test_men : fit.test_women)++;
  if (fit.train_men == 0 || fit.train_women == 0 || fit.test_men == 0 || fit.test_women == 0)
    return Error{"ANSUR II: each set needs both men and women"};

  for (const std::string& target : spine_targets()) {
    auto baseline = fit_ols(train, target, {"stature"});
    if (!baseline) return baseline.error();
    for (bool with_sex : {false, true}) {
      std::vector<std::string> inputs = silhouette_inputs();
      if (with_sex) inputs.emplace_back(kMaleInput);
      auto model = fit_ols(train, target, inputs);
      if (!model) return model.error();
      FittedTarget t{*model, *baseline, {}, {}, {}, {}};
      for (auto [stats, m, set] : {std::tuple{&t.train, &t.model, &train}, std::tuple{&t.test, &t.model, &test},
                                   std::tuple{&t.baseline_train, &t.baseline, &train},
                                   std::tuple{&t.baseline_test, &t.baseline, &test}}) {
        auto r = residuals(*m, *set);
        if (!r) return r.error();
        *stats = *r;
      }
      fit.targets.push_back(std::move(t));
    }
  }
  return fit;
}

namespace {

std::string number(double v) { return fmt::format("{:.10g}", v); }

// Residual figures to 0.1 µm: a training mean of 1e-12 is a zero, not a
// figure, and "-0.0000" would read as if it had a sign.
std::string mm(double v) { return fmt::format("{:.4f}", std::round(v * 1e4) / 1e4 + 0.0); }

void write_stats(std::string& out, std::string_view prefix, const ResidualStats& s) {
  out += fmt::format("{0}_mean = {1}\n{0}_sd = {2}\n{0}_p95_abs = {3}\n{0}_max_abs = {4}\n", prefix, mm(s.mean),
                     mm(s.sd), mm(s.p95_abs), mm(s.max_abs));
}

}  // namespace

std::string to_toml(const AnthropometryFit& fit) {
  std::string out;
  out += "# Anthropometric regressions: the skin heights of C7 (cervicale) and of\n"
         "# the iliac crest (iliocristale), which the silhouettes do not show, from\n"
         "# the measurements a frontal and a lateral silhouette give. T1 and L5 are\n"
         "# placed from these landmarks as docs/anthropometry.md describes.\n"
         "#\n"
         "# Source: ANSUR II, the 2012 U.S. Army Anthropometric Survey public release\n"
         "# (Gordon et al. 2014, \"2012 Anthropometric Survey of U.S. Army Personnel:\n"
         "# Methods and Summary Statistics\", NATICK/TR-15/007): 6 068 adults measured by\n"
         "# trained measurers; ../shared/data/ansur2/.\n"
         "#\n"
         "# Generated, do not edit: spinewatch fit-anthropometry --ansur ../shared/data/ansur2\n"
         "#   --out config/anthropometry.toml  (tests/tools/anthropometry regenerate it and compare).\n"
         "# Ordinary least squares with an intercept, fitted on the training subjects only.\n"
         "# Split: a subject is a test subject when splitmix64(SubjectId) mod 10 < 3.\n"
         "# Inputs are ANSUR column names, standing, in mm; `male` is 1 for a man, 0 for a\n"
         "# woman (the station usually does not know it: prefer the model without it).\n"
         "# Residuals are measured − predicted, mm; sd is the sample SD, p95_abs the 95th\n"
         "# percentile of |residual|. stature_only is the baseline: the same target from\n"
         "# stature alone, fitted on the same subjects.\n\n";
  out += fmt::format("[source]\ndataset = \"ANSUR II\"\nreference = \"Gordon et al. 2014, NATICK/TR-15/007\"\n"
                     "split = \"test when splitmix64(SubjectId) mod 10 < 3\"\n"
                     "train_men = {}\ntrain_women = {}\ntest_men = {}\ntest_women = {}\n",
                     fit.train_men, fit.train_women, fit.test_men, fit.test_women);
  for (const FittedTarget& t : fit.targets) {
    const LinearRegression& m = t.model;
    out += fmt::format("\n[[regression]]\ntarget = \"{}\"\n", m.target);
    out += "inputs = [";
    for (std::size_t i = 0; i < m.inputs.size(); ++i) out += fmt::format("{}\"{}\"", i ? ", " : "", m.inputs[i]);
    out += "]\n";
    out += fmt::format("intercept = {}\ncoefficients = [\n", number(m.intercept));
    for (std::size_t i = 0; i < m.inputs.size(); ++i)
      out += fmt::format("  {},  # {}\n", number(m.coefficients[i]), m.inputs[i]);
    out += "]\n";
    out += fmt::format("# SD of the residuals on the training subjects (the model's uncertainty).\nresidual_sd = {}\n",
                       number(m.residual_sd));
    out += "[regression.residuals]\n";
    write_stats(out, "train", t.train);
    write_stats(out, "test", t.test);
    out += fmt::format("[regression.stature_only]\nintercept = {}\nstature = {}\n", number(t.baseline.intercept),
                       number(t.baseline.coefficients.at(0)));
    write_stats(out, "train", t.baseline_train);
    write_stats(out, "test", t.baseline_test);
  }
  return out;
}

std::string report(const AnthropometryFit& fit) {
  std::string out = fmt::format("ANSUR II: train {} men + {} women, test {} men + {} women\n", fit.train_men,
                                fit.train_women, fit.test_men, fit.test_women);
  out += fmt::format("{:<20} {:<14} {:<6} {:>8} {:>8} {:>10} {:>8}\n", "target", "model", "set", "mean", "SD",
                     "p95 |e|", "max |e|");
  auto row = [&](const std::string& target, std::string_view model, std::string_view set, const ResidualStats& s) {
    out += fmt::format("{:<20} {:<14} {:<6} {:>8.2f} {:>8.2f} {:>10.2f} {:>8.2f}\n", target, model, set, s.mean, s.sd,
                       s.p95_abs, s.max_abs);
  };
  for (std::size_t i = 0; i < fit.targets.size(); ++i) {
    const FittedTarget& t = fit.targets[i];
    const bool sex = t.model.uses(kMaleInput);
    const std::string_view name = sex ? "silhouette+sex" : "silhouette";
    // The baseline is the same for both models of a target: print it once.
    if (!sex) {
      row(t.model.target, "stature only", "train", t.baseline_train);
      row(t.model.target, "stature only", "test", t.baseline_test);
    }
    row(t.model.target, name, "train", t.train);
    row(t.model.target, name, "test", t.test);
  }
  out += "residual = measured − predicted, mm; SD sample; p95 nearest rank\n";
  return out;
}

}  // namespace spinewatch::anthropometry
