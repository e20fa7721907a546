// The regressions on the real ANSUR II release (../shared/data/ansur2).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <toml++/toml.h>

#include "spinewatch/anthropometry/fit.hpp"
#include "spinewatch/anthropometry/split.hpp"
#include "test_support.hpp"

namespace spinewatch::anthropometry {
namespace {

const AnthropometryFit& release_fit() {
  static const AnthropometryFit fit = [] {
    auto subjects = read_ansur(test::source_path(std::string(kAnsurRelativeDir)));
    if (!subjects) throw std::runtime_error(subjects.error().message);
    auto f = fit_anthropometry(*subjects);
    if (!f) throw std::runtime_error(f.error().message);
    return std::move(f).value();
  }();
  return fit;
}

TEST(AnthropometryFit, OlsRecoversAnExactLinearRelation) {
  // cervicale = 20 + 0.8 stature + 0.1 hipbreadth, exactly: the fit returns it.
  std::vector<AnsurSubject> subjects;
  for (int i = 0; i < 50; ++i) {
    AnsurSubject s;
    s.id = i + 1;
    s.stature_mm = 1500 + 7.0 * i;
    s.hip_breadth_mm = 300 + double((i * 37) % 60);
    s.cervicale_height_mm = 20 + 0.8 * s.stature_mm + 0.1 * s.hip_breadth_mm;
    subjects.push_back(s);
  }
  auto r = fit_ols(subjects, "cervicaleheight", {"stature", "hipbreadth"});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_NEAR(r->intercept, 20, 1e-6);
  EXPECT_NEAR(r->coefficients[0], 0.8, 1e-9);
  EXPECT_NEAR(r->coefficients[1], 0.1, 1e-9);
  EXPECT_NEAR(r->residual_sd, 0, 1e-6);
  auto dependent = fit_ols(subjects, "cervicaleheight", {"stature", "stature"});
  EXPECT_FALSE(dependent.ok());
}

// What a silhouette measures predicts C7 and the iliac crest better than
// stature alone, on people the fit never saw.
TEST(AnthropometryFit, TestSetBeatsTheStatureOnlyBaseline) {
  const AnthropometryFit& fit = release_fit();
  ASSERT_EQ(fit.targets.size(), 4u);  // two targets × (without, with sex)
  EXPECT_GT(fit.test_men, 1000u);
  EXPECT_GT(fit.test_women, 500u);
  for (const FittedTarget& t : fit.targets) {
    SCOPED_TRACE(t.model.target + (t.model.uses(kMaleInput) ? " with sex" : " without sex"));
    EXPECT_EQ(t.test.n, fit.test_men + fit.test_women);
    EXPECT_LT(t.test.sd, 0.9 * t.baseline_test.sd);  // at least 10 % tighter
    EXPECT_LT(t.test.p95_abs, t.baseline_test.p95_abs);
    EXPECT_LT(std::abs(t.test.mean), 2.0);  // no bias on the unseen set
    // Held-out error close to the training error: not an overfit.
    EXPECT_LT(t.test.sd, 1.1 * t.train.sd);
  }
}

// Every number of two anthropometry files, compared leaf by leaf.
void expect_same_numbers(const toml::node& a, const toml::node& b, const std::string& path) {
  if (a.is_table()) {
    ASSERT_TRUE(b.is_table()) << path;
    const auto& ta = *a.as_table();
    const auto& tb = *b.as_table();
    EXPECT_EQ(ta.size(), tb.size()) << path;
    for (const auto& [key, value] : ta) {
      const toml::node* other = tb.get(key.str());
      ASSERT_NE(other, nullptr) << path << "." << key.str() << " missing from the committed file";
      expect_same_numbers(value, *other, path + "." + std::string(key.str()));
    }
  } else if (a.is_array()) {
    ASSERT_TRUE(b.is_array()) << path;
    ASSERT_EQ(a.as_array()->size(), b.as_array()->size()) << path;
    for (std::size_t i = 0; i < a.as_array()->size(); ++i)
      expect_same_numbers(*a.as_array()->get(i), *b.as_array()->get(i), path + "[" + std::to_string(i) + "]");
  } else if (a.is_number()) {
    ASSERT_TRUE(b.is_number()) << path;
    const double x = *a.value<double>(), y = *b.value<double>();
    EXPECT_NEAR(x, y, 1e-7 * std::max(1.0, std::abs(y))) << path;
  } else {
    EXPECT_EQ(a.value<std::string>(), b.value<std::string>()) << path;
  }
}

// config/anthropometry.toml is what the command makes from the release.
TEST(AnthropometryFit, CommittedFileIsRegeneratedFromTheRelease) {
  test::TempDir dir;
  const auto out = dir / "anthropometry.toml";
  const auto ansur = test::source_path(std::string(kAnsurRelativeDir));
  const test::CommandResult run =
      test::run_cli("fit-anthropometry --ansur '" + ansur.string() + "' --out '" + out.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("stature only"), std::string::npos) << run.output;
  const toml::table fresh = toml::parse_file(out.string());
  const toml::table committed = toml::parse_file(test::source_path("config/anthropometry.toml").string());
  expect_same_numbers(fresh, committed, "");
  // And the estimator reads it.
  auto model = parse_anthropometry(test::read_file(test::source_path("config/anthropometry.toml")), "anthropometry.toml");
  ASSERT_TRUE(model) << model.error().message;
  for (const std::string& target : spine_targets()) {
    EXPECT_NE(model->find(target, false), nullptr) << target;
    EXPECT_NE(model->find(target, true), nullptr) << target;
  }
}

TEST(AnthropometryFit, BadDirectoryExitsOneNamingTheFile) {
  test::TempDir dir;
  const test::CommandResult run = test::run_cli("fit-anthropometry --ansur /nonexistent --out '" + (dir / "a.toml").string() + "'");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("/nonexistent/ANSUR_II_MALE_Public.csv: cannot open"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "a.toml"));
}

}  // namespace
}  // namespace spinewatch::anthropometry
