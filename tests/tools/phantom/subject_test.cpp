#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/phantom/subject.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

using nlohmann::json;

json generic_json() { return json::parse(test::read_file(test::source_path("config/subjects/generic.json"))); }

TEST(PhantomSubject, ShippedSubjectsLoad) {
  auto generic = load_subject(test::source_path("config/subjects/generic.json"));
  auto petite = load_subject(test::source_path("config/subjects/petite.json"));
  auto tall = load_subject(test::source_path("config/subjects/tall.json"));
  ASSERT_TRUE(generic) << generic.error().message;
  ASSERT_TRUE(petite) << petite.error().message;
  ASSERT_TRUE(tall) << tall.error().message;
  // The generic subject is the estimator's generic model, and the built-in
  // default (no --subject) is exactly the shipped file.
  EXPECT_EQ(generic->height_mm, generic_spine_spec().reference_height_mm);
  EXPECT_EQ(to_json(*generic), to_json(Subject{}));
  EXPECT_NEAR(petite->height_mm, 1600, 30);
  EXPECT_NEAR(tall->height_mm, 1900, 30);
  EXPECT_GT(tall->shoulder_width_mm, generic->shoulder_width_mm);
  // Petite: a different waist/hip ratio, not just a scaled generic.
  const double generic_ratio = generic->waist.half_width_mm / generic->hips.half_width_mm;
  const double petite_ratio = petite->waist.half_width_mm / petite->hips.half_width_mm;
  EXPECT_LT(petite_ratio, generic_ratio - 0.1);
}

TEST(PhantomSubject, JsonRoundTrip) {
  auto subject = parse_subject(generic_json(), "generic.json");
  ASSERT_TRUE(subject) << subject.error().message;
  subject->posture = SubjectPosture::Seated;
  subject->joint_factors.emplace();
  for (std::size_t i = 0; i < kJointCount; ++i) (*subject->joint_factors)[i] = {0.9 + 0.01 * double(i), 1.1, 1.0};
  auto again = parse_subject(to_json(*subject), "again");
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(to_json(*again), to_json(*subject));
  EXPECT_EQ(again->posture, SubjectPosture::Seated);
}

TEST(PhantomSubject, SpineDepthMayBeOneNumber) {
  json j = generic_json();
  j["spine_depth_mm"] = 65;
  auto subject = parse_subject(j, "s.json");
  ASSERT_TRUE(subject) << subject.error().message;
  EXPECT_EQ(subject->spine_depth_thoracic_mm, 65);
  EXPECT_EQ(subject->spine_depth_lumbar_mm, 65);
}

struct BadCase {
  const char* what;
  void (*edit)(json&);
  const char* expected;  // in the message, after the file name
};

TEST(PhantomSubject, BadFilesNameTheFieldAndTheProblem) {
  const BadCase cases[] = {
      {"missing", [](json& j) { j.erase("mass_kg"); }, "mass_kg: missing"},
      {"wrong type", [](json& j) { j["height_mm"] = "tall"; }, "height_mm: expected a number"},
      {"out of range", [](json& j) { j["height_mm"] = 400; }, "height_mm: 400 is out of range"},
      {"nested missing", [](json& j) { j["trunk"]["waist"].erase("half_depth_mm"); }, "trunk.waist.half_depth_mm: missing"},
      {"nested range", [](json& j) { j["legs"]["thigh_radius_mm"] = -3; }, "legs.thigh_radius_mm: -3 is out of range"},
      {"unknown", [](json& j) { j["hieght_mm"] = 1700; }, "hieght_mm: unknown field"},
      {"nested unknown", [](json& j) { j["arms"]["lenght_mm"] = 1; }, "arms.lenght_mm: unknown field"},
      // Found by the phantom_subject fuzzer: a line end in the key stays quoted.
      {"line end in a key", [](json& j) { j["legs"]["le\ngth_mm"] = 1; }, "legs.le\\ngth_mm: unknown field"},
      {"posture", [](json& j) { j["posture"] = "lying"; }, "posture: \"lying\" is not"},
      {"not an object", [](json& j) { j["head"] = 3; }, "head: expected an object"},
      {"spine outside", [](json& j) {
         j["trunk"]["chest"]["half_depth_mm"] = 60;
         j["spine_depth_mm"]["thoracic"] = 110;
       }, "spine_depth_mm.thoracic: puts the spine outside"},
      {"factors count", [](json& j) { j["joint_factors"] = json::array({{{"flexion", 1}, {"lateral", 1}, {"twist", 1}}}); },
       "joint_factors: expected 16 entries"},
      {"factor field", [](json& j) {
         j["joint_factors"] = json::array();
         for (int i = 0; i < 16; ++i) j["joint_factors"].push_back({{"flexion", 1}, {"lateral", 1}, {"twist", 1}});
         j["joint_factors"][3]["twist"] = 0;
       }, "joint_factors[3].twist: 0 is out of range"},
  };
  for (const BadCase& c : cases) {
    json j = generic_json();
    c.edit(j);
    auto subject = parse_subject(j, "bad.json");
    ASSERT_FALSE(subject) << c.what;
    EXPECT_EQ(subject.error().message.rfind("bad.json: ", 0), 0u) << c.what << ": " << subject.error().message;
    EXPECT_NE(subject.error().message.find(c.expected), std::string::npos) << c.what << ": " << subject.error().message;
  }
}

TEST(PhantomSubject, UnreadableOrMalformedFileNamesTheFile) {
  test::TempDir dir;
  auto missing = load_subject(dir / "nope.json");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("nope.json: cannot open"), std::string::npos) << missing.error().message;
  test::write_file(dir / "broken.json", "{\"height_mm\": 1750,\n \"mass_kg\": }\n");
  auto broken = load_subject(dir / "broken.json");
  ASSERT_FALSE(broken);
  EXPECT_NE(broken.error().message.find("broken.json: not valid JSON"), std::string::npos) << broken.error().message;
  EXPECT_NE(broken.error().message.find("line 2"), std::string::npos) << broken.error().message;
  test::write_file(dir / "huge.json", "{\"height_mm\": 1750,\n \"mass_kg\": -1e400}\n");
  auto huge = load_subject(dir / "huge.json");
  ASSERT_FALSE(huge);
  EXPECT_EQ(huge.error().message, (dir / "huge.json").string() + ": not valid JSON: line 2: number overflow parsing '-1e400'");
}

}  // namespace
}  // namespace spinewatch::phantom
