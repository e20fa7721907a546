// Phantom subjects from measured adults (ANSUR II, ../shared/data/ansur2).
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/phantom/ansur_subject.hpp"
#include "spinewatch/phantom/body.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

using nlohmann::json;

std::filesystem::path ansur_dir() { return test::source_path(std::string(anthropometry::kAnsurRelativeDir)); }

const std::vector<anthropometry::AnsurSubject>& release() {
  static const std::vector<anthropometry::AnsurSubject> rows = [] {
    auto r = anthropometry::read_ansur(ansur_dir());
    if (!r) throw std::runtime_error(r.error().message);
    return std::move(r).value();
  }();
  return rows;
}

// Top of the head in the neutral pose (body.cpp's head above T1).
double head_top(const BodyModel& body) {
  const Subject& s = body.subject();
  const double scale = size_scale(generic_spine_spec(), s.height_mm);
  return body.neutral()[kNeckIndex].body_center.y() + 30 * scale + s.neck_length_mm + 1.75 * s.head_half_height_mm;
}

// The first man of the release: stature 1776, cervicale 1535, iliac crest
// 1071, sitting height 928, 81.5 kg (his row of ANSUR_II_MALE_Public.csv).
TEST(AnsurSubject, KnownManPlacesT1AndL5FromHisLandmarks) {
  auto s = load_ansur_subject("ansur:10027", ansur_dir(), RuleDraw::Mean);
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(s->name, "ansur:10027");
  EXPECT_EQ(s->height_mm, 1776);
  EXPECT_DOUBLE_EQ(s->mass_kg, 81.5);
  EXPECT_EQ(*s->t1_height_mm, 1535 - 15);  // C7 tip − 15 mm
  EXPECT_EQ(*s->l5_height_mm, 1071 - 25);  // iliac crest − 25 mm (men)
  EXPECT_EQ(*s->sitting_height_mm, 928);
  EXPECT_EQ(s->shoulder_width_mm, 493);    // bideltoid breadth
  EXPECT_EQ(s->waist.half_depth_mm, 120);  // waist depth 240 / 2

  const BodyModel standing(*s, SubjectPosture::Standing, 1);
  EXPECT_NEAR(standing.neutral()[kNeckIndex].body_center.y(), 1520, 1e-9);
  EXPECT_NEAR(standing.neutral()[kWaistIndex].body_center.y(), 1046, 1e-9);
  EXPECT_NEAR(head_top(standing), 1776, 1e-9);
  // Seated, the spine keeps its length and the head tops the sitting height.
  const BodyModel seated(*s, SubjectPosture::Seated, 1);
  EXPECT_NEAR(head_top(seated) - s->seat_height_mm, 928, 1e-9);
  EXPECT_NEAR(seated.neutral()[kNeckIndex].body_center.y() - seated.neutral()[kWaistIndex].body_center.y(), 474, 1e-9);
}

TEST(AnsurSubject, KnownWomanUsesTheWomensCrestRule) {
  auto s = load_ansur_subject("ansur:10037", ansur_dir(), RuleDraw::Mean);  // stature 1560, cervicale 1336, crest 966
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(*s->t1_height_mm, 1336 - 15);
  EXPECT_EQ(*s->l5_height_mm, 966 - 10);
  const BodyModel body(*s, SubjectPosture::Standing, 2);
  EXPECT_NEAR(body.neutral()[kWaistIndex].body_center.y(), 956, 1e-9);
  EXPECT_NEAR(head_top(body), 1560, 1e-9);
}

TEST(AnsurSubject, UnknownOrMalformedIdIsAClearError) {
  auto unknown = load_ansur_subject("ansur:1", ansur_dir());
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("ansur:1: no subject with SubjectId 1 in"), std::string::npos)
      << unknown.error().message;
  for (const char* spec : {"ansur:", "ansur:12x", "ansur:-4"}) {
    auto bad = load_ansur_subject(spec, ansur_dir());
    ASSERT_FALSE(bad.ok()) << spec;
    EXPECT_NE(bad.error().message.find("is not a SubjectId"), std::string::npos) << bad.error().message;
  }
  auto no_data = load_ansur_subject("ansur:10027", "/nonexistent");
  ASSERT_FALSE(no_data.ok());
  EXPECT_NE(no_data.error().message.find("/nonexistent/ANSUR_II_MALE_Public.csv: cannot open"), std::string::npos);
}

// Every measured adult makes a subject the file format accepts, with its
// spine where its landmarks put it.
TEST(AnsurSubject, EveryRowOfTheReleaseIsAValidSubject) {
  ASSERT_EQ(release().size(), 6068u);
  for (const auto& row : release()) {
    auto s = subject_from_ansur(row);
    ASSERT_TRUE(s) << row.id << ": " << s.error().message;
    const BodyModel body(*s, SubjectPosture::Standing, 1);
    const RuleDeviation dev = draw_rule_deviation(row.id, default_spine_depth());
    ASSERT_NEAR(body.neutral()[kNeckIndex].body_center.y(), row.cervicale_height_mm - 15 - dev.t1_below_cervicale_mm, 1e-6)
        << row.id;
    ASSERT_GE(*s->l5_height_mm, row.trochanterion_height_mm + 40) << row.id;
    ASSERT_NEAR(head_top(body), row.stature_mm, 1e-6) << row.id;
  }
}

// The validation protocol (config/spine-depth.toml): each subject's
// offsets and spine depth drawn from the rules' distributions, the same
// for a subject every time, and over the release as published — mean 0,
// SD the rule's (clamped at ±2 SD: 0.96 of it), never beyond the clamp.
TEST(AnsurSubject, RulesAreDrawnPerSubjectFromTheirPublishedSpread) {
  const SpineDepthRule& rule = default_spine_depth();
  const double sd[] = {rule.t1_below_cervicale_sd_mm(), rule.l5_below_iliocristale_sd_mm(),
                       rule.sd_mm(SpineRegion::Thoracic), rule.sd_mm(SpineRegion::Lumbar)};
  double sum[4] = {}, sq[4] = {};
  for (const auto& row : release()) {
    const RuleDeviation d = draw_rule_deviation(row.id, rule);
    const RuleDeviation again = draw_rule_deviation(row.id, rule);
    ASSERT_EQ(d.lumbar_depth_mm, again.lumbar_depth_mm);
    const double v[] = {d.t1_below_cervicale_mm, d.l5_below_iliocristale_mm, d.thoracic_depth_mm, d.lumbar_depth_mm};
    for (int k = 0; k < 4; ++k) {
      ASSERT_LE(std::abs(v[k]), 2.0 * sd[k] * 1.0001 + (k >= 2 ? 2.0 * sd[k] : 0)) << row.id;
      sum[k] += v[k];
      sq[k] += v[k] * v[k];
    }
  }
  const double n = double(release().size());
  for (int k = 0; k < 4; ++k) {
    const double mean = sum[k] / n, spread = std::sqrt(sq[k] / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.05 * sd[k]) << k;
    EXPECT_NEAR(spread / sd[k], 0.96, 0.03) << k;
  }
  // The drawn subject carries them: depth at its BMI plus its deviation.
  const auto& row = release().front();
  auto drawn = subject_from_ansur(row);
  auto mean = subject_from_ansur(row, RuleDraw::Mean);
  ASSERT_TRUE(drawn && mean);
  const RuleDeviation d = draw_rule_deviation(row.id, rule);
  EXPECT_NEAR(drawn->spine_depth_lumbar_mm - mean->spine_depth_lumbar_mm, d.lumbar_depth_mm, 1e-9);
  EXPECT_NEAR(*mean->l5_height_mm - *drawn->l5_height_mm, d.l5_below_iliocristale_mm, 1e-9);
  const double bmi = row.mass_kg / std::pow(row.stature_mm / 1000.0, 2);
  EXPECT_NEAR(mean->spine_depth_thoracic_mm, rule.mean_mm(SpineRegion::Thoracic, bmi), 1e-9);
}

TEST(AnsurSubject, LandmarksRoundTripThroughJson) {
  auto s = load_ansur_subject("ansur:10027", ansur_dir(), RuleDraw::Mean);
  ASSERT_TRUE(s) << s.error().message;
  const json j = to_json(*s);
  EXPECT_EQ(j["spine_heights_mm"]["t1"], 1520);
  EXPECT_EQ(j["hip_joint_height_mm"], 919);
  auto again = parse_subject(j, "again");
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(to_json(*again), j);
  // Without landmarks nothing new is written: the shipped files are unchanged.
  EXPECT_FALSE(to_json(Subject{}).contains("spine_heights_mm"));
  EXPECT_FALSE(to_json(Subject{}).contains("sitting_height_mm"));
}

TEST(AnsurSubject, BadLandmarksNameTheField) {
  auto s = load_ansur_subject("ansur:10027", ansur_dir(), RuleDraw::Mean);
  ASSERT_TRUE(s) << s.error().message;
  struct Case {
    void (*edit)(json&);
    const char* expected;
  };
  const Case cases[] = {
      {[](json& j) { j["spine_heights_mm"].erase("l5"); }, "x.json: spine_heights_mm.l5: missing"},
      {[](json& j) { j["spine_heights_mm"]["t1"] = 1100; }, "x.json: spine_heights_mm.t1: T1 54 mm above L5 is outside"},
      {[](json& j) { j["spine_heights_mm"]["t2"] = 1; }, "x.json: spine_heights_mm.t2: unknown field"},
      {[](json& j) { j["shoulder_height_mm"] = 1200; }, "x.json: shoulder_height_mm: 1200 is more than"},
      {[](json& j) { j["hip_joint_height_mm"] = 1040; }, "x.json: hip_joint_height_mm: 1040 must lie"},
      {[](json& j) { j["sitting_height_mm"] = "tall"; }, "x.json: sitting_height_mm: expected a number"},
  };
  for (const Case& c : cases) {
    json j = to_json(*s);
    c.edit(j);
    auto r = parse_subject(j, "x.json");
    ASSERT_FALSE(r.ok()) << c.expected;
    EXPECT_NE(r.error().message.find(c.expected), std::string::npos) << r.error().message;
  }
}

TEST(AnsurSubject, CliRendersAMeasuredAdult) {
  test::TempDir dir;
  const std::string env = "SPINEWATCH_ANSUR_DIR='" + ansur_dir().string() + "' ";
  auto r = test::run_command(env + test::cli_path() + " phantom --scenario upright --frames 2 --empty-frames 1 --subject ansur:10027 --out " +
                             (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json recording = json::parse(test::read_file(dir / "rec" / "recording.json"));
  EXPECT_EQ(recording["subject"]["name"], "ansur:10027");
  // The CLI's subject is the validation protocol's: his drawn offsets.
  const RuleDeviation dev = draw_rule_deviation(10027, default_spine_depth());
  EXPECT_NEAR(recording["subject"]["spine_heights_mm"]["l5"].get<double>(), 1046 - dev.l5_below_iliocristale_mm, 1e-6);
  // The ground truth's neck is T1 at his landmark, give or take the sway.
  const std::string truth = test::read_file(dir / "rec" / "ground_truth.ndjson");
  const std::size_t second = truth.find('\n') + 1;  // the first line is the empty frame
  const json person = json::parse(truth.substr(second, truth.find('\n', second) - second));
  EXPECT_NEAR(person["neck"][1].get<double>(), 1520 - dev.t1_below_cervicale_mm, 10) << person.dump();

  auto unknown = test::run_command(env + test::cli_path() + " phantom --scenario upright --subject ansur:1 --out " +
                                   (dir / "rec2").string());
  EXPECT_EQ(unknown.exit_code, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("ansur:1: no subject with SubjectId 1"), std::string::npos) << unknown.output;
}

}  // namespace
}  // namespace spinewatch::phantom
