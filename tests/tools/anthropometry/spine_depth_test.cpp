// The spine's depth behind the back skin (anatomy/spine_depth.hpp,
// config/spine-depth.toml): the rule as published, its BMI from the
// outline refitted from the ANSUR II training subjects and checked on the
// test subjects, and its file's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/anthropometry/split.hpp"
#include "spinewatch/estimator/anatomy/spine_depth.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using anthropometry::Partition;

double bmi(const anthropometry::AnsurSubject& s) { return s.mass_kg / std::pow(s.stature_mm / 1000.0, 2); }

TEST(SpineDepth, IsSoftTissueGrowingWithBmiPlusBone) {
  const SpineDepthRule& r = default_spine_depth();
  // At BMI 25: skin to canal 45 (thoracic) / 42.2 (lumbar) + canal 15 + half body 12 / 17.5.
  EXPECT_NEAR(r.mean_mm(SpineRegion::Thoracic, 25), 72.0, 1e-9);
  EXPECT_NEAR(r.mean_mm(SpineRegion::Lumbar, 25), 74.7, 1e-9);
  // 1 mm per kg/m² of BMI: an obese worker's (BMI 35) lumbar spine 10 mm deeper.
  EXPECT_NEAR(r.mean_mm(SpineRegion::Lumbar, 35) - r.mean_mm(SpineRegion::Lumbar, 25), 10.0, 1e-9);
  EXPECT_NEAR(r.sd_mm(SpineRegion::Lumbar), std::sqrt(8.0 * 8.0 + 2.5 * 2.5 + 1.5 * 1.5), 1e-9);
  EXPECT_NEAR(r.sd_mm(SpineRegion::Thoracic), std::sqrt(8.0 * 8.0 + 2.0 * 2.0 + 2.5 * 2.5), 1e-9);
  EXPECT_EQ(region_of(11), SpineRegion::Thoracic);  // T12
  EXPECT_EQ(region_of(12), SpineRegion::Lumbar);    // L1
  EXPECT_EQ(r.t1_below_cervicale_sd_mm(), 10.0);
  EXPECT_EQ(r.l5_below_iliocristale_sd_mm(), 15.0);
}

const std::vector<anthropometry::AnsurSubject>& release() {
  static const auto subjects = [] {
    auto all = anthropometry::read_ansur(test::source_path(std::string(anthropometry::kAnsurRelativeDir)));
    if (!all) throw std::runtime_error(all.error().message);
    return std::move(all).value();
  }();
  return subjects;
}

// The committed outline-BMI coefficients are the least-squares fit on the
// training subjects, and on the test subjects they do as well.
TEST(SpineDepth, OutlineBmiIsFittedOnTrainingAndHoldsOnTestSubjects) {
  const auto train = anthropometry::subjects_in(release(), Partition::Train);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(train.size()), 3);
  Eigen::VectorXd y(a.rows());
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    const auto& s = train[static_cast<std::size_t>(i)];
    a.row(i) << 1.0, s.waist_depth_mm, s.stature_mm;
    y(i) = bmi(s);
  }
  const Eigen::Vector3d c = a.colPivHouseholderQr().solve(y);
  const SpineDepthRule& r = default_spine_depth();
  for (double depth : {180.0, 240.0, 320.0})
    for (double stature : {1500.0, 1750.0, 1950.0})
      // To the committed rounding (6 decimals): within 0.002 kg/m², 0.002 mm of depth.
      EXPECT_NEAR(r.bmi_from_outline(depth, stature), c(0) + c(1) * depth + c(2) * stature, 2e-3) << depth << " " << stature;

  for (Partition set : {Partition::Train, Partition::Test}) {
    double sum = 0, sq = 0;
    const auto people = anthropometry::subjects_in(release(), set);
    for (const auto& s : people) {
      const double e = bmi(s) - r.bmi_from_outline(s.waist_depth_mm, s.stature_mm);
      sum += e;
      sq += e * e;
    }
    const double n = double(people.size()), mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
    EXPECT_LT(std::abs(mean), 0.2) << anthropometry::to_string(set);
    EXPECT_NEAR(sd, r.outline_bmi_sd(), 0.1) << anthropometry::to_string(set);  // 1.93 train, 1.95 test
  }
}

TEST(SpineDepth, ABadFileNamesTheKeyAndLine) {
  const std::string text(embedded_spine_depth_toml());
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    auto r = SpineDepthRule::parse(t, "spine-depth.toml");
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.error().message;
  };
  EXPECT_NE(broken("canal_mm = 15.0           # [Cs]", "# gone").find("spine-depth.toml:"), std::string::npos);
  EXPECT_NE(broken("canal_mm = 15.0           # [Cs]", "# gone").find("lumbar.canal_mm: missing"), std::string::npos);
  EXPECT_NE(broken("tissue_per_bmi = 1.0      # [La]", "tissue_per_bmi = \"one\"  #").find("thoracic.tissue_per_bmi: expected a number"),
            std::string::npos);
  EXPECT_NE(broken("truncate_sd = 2.0", "truncate_sd = 9.0").find("placement.truncate_sd: 9 is out of range"),
            std::string::npos);
  EXPECT_NE(broken("[outline_bmi]", "[outline]").find("[outline_bmi]: missing"), std::string::npos);
}

}  // namespace
}  // namespace spinewatch
