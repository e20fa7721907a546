#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include <cmath>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "spinewatch/anthropometry/ansur.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/phantom/scenario.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

TEST(PhantomCli, ListsEveryScenario) {
  auto r = test::run_cli("phantom --list");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const Scenario& s : scenarios()) EXPECT_NE(r.output.find(std::string(s.name) + " "), std::string::npos) << s.name;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), std::ptrdiff_t(scenarios().size()));
}

TEST(PhantomCli, WritesARecording) {
  test::TempDir dir;
  auto r = test::run_cli("phantom --scenario fast --frames 20 --empty-frames 2 --seed 3 --shadow --subject " +
                         test::source_path("config/subjects/tall.json").string() + " --out " + (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"frontal.raw", "lateral.raw", "recording.json", "calibration.yaml", "ground_truth.ndjson",
                           "background_frontal.png", "background_lateral.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "rec" / file)) << file;
  EXPECT_EQ(std::filesystem::file_size(dir / "rec" / "frontal.raw"), 22u * 320 * 240 * 2);
  const std::string truth = test::read_file(dir / "rec" / "ground_truth.ndjson");
  EXPECT_EQ(std::count(truth.begin(), truth.end(), '\n'), 22);
  EXPECT_NE(test::read_file(dir / "rec" / "recording.json").find("\"tall\""), std::string::npos);
  // A named subject keeps the generic anatomy: the tool says how to score it.
  EXPECT_NE(r.output.find("subject 'tall' has the phantom's generic anatomy"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("spine_placement = \"generic\""), std::string::npos) << r.output;
}

// A measured adult's spine is placed from the row's own landmarks: no such note.
TEST(PhantomCli, AMeasuredAdultNeedsNoNoteOnItsAnatomy) {
  test::TempDir dir;
  // The child inherits the variable: the data beside the source tree.
  ::setenv("SPINEWATCH_ANSUR_DIR", test::source_path(std::string(anthropometry::kAnsurRelativeDir)).c_str(), 1);
  auto r = test::run_cli("phantom --scenario upright --frames 2 --empty-frames 0 --subject ansur:15936 --out " +
                         (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("generic anatomy"), std::string::npos) << r.output;
}

// The default subject is the measured adult ANSUR II 15936, embedded
// (config/subjects/ansur-15936.json): the same person `--subject
// ansur:15936` reads from the data, so the committed file cannot drift from
// it; the generic anatomy is had by name.
TEST(PhantomCli, TheDefaultSubjectIsTheMeasuredAdultAndGenericIsByName) {
  test::TempDir dir;
  const std::string args = "--log-level warn phantom --scenario upright --frames 1 --empty-frames 0 --seed 4 --out ";
  auto r = test::run_cli(args + (dir / "default").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto subject = [&](const char* name) {
    return nlohmann::json::parse(test::read_file(dir / name / "recording.json"))["subject"];
  };
  const auto by_default = subject("default");
  EXPECT_EQ(by_default["name"], "ansur:15936");
  EXPECT_TRUE(by_default.contains("spine_heights_mm")) << by_default.dump();
  auto generic = test::run_cli(args + (dir / "generic").string() + " --subject generic");
  ASSERT_EQ(generic.exit_code, 0) << generic.output;
  EXPECT_EQ(subject("generic")["name"], "generic");
  EXPECT_FALSE(subject("generic").contains("spine_heights_mm"));

  const auto ansur_dir = test::source_path(std::string(anthropometry::kAnsurRelativeDir));
  if (!std::filesystem::exists(ansur_dir)) GTEST_SKIP() << ansur_dir << " is not here: the comparison with the data is skipped";
  ::setenv("SPINEWATCH_ANSUR_DIR", ansur_dir.c_str(), 1);
  auto measured = test::run_cli(args + (dir / "ansur").string() + " --subject ansur:15936");
  ASSERT_EQ(measured.exit_code, 0) << measured.output;
  EXPECT_EQ(by_default, subject("ansur")) << "config/subjects/ansur-15936.json differs from the data's subject 15936";
}

TEST(PhantomCli, UnknownScenarioExitsTwo) {
  test::TempDir dir;
  auto r = test::run_cli("phantom --scenario backflip --out " + (dir / "rec").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("backflip"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "rec"));
}

TEST(PhantomCli, AChairForAStandingSubjectOrOfAnUnknownColourExitsTwo) {
  test::TempDir dir;
  auto standing = test::run_cli("phantom --scenario upright --chair black --out " + (dir / "rec").string());
  EXPECT_EQ(standing.exit_code, 2) << standing.output;
  EXPECT_NE(standing.output.find("a chair needs a seated scenario"), std::string::npos) << standing.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "rec"));
  auto colour = test::run_cli("phantom --scenario typing --chair purple --out " + (dir / "rec").string());
  EXPECT_EQ(colour.exit_code, 2) << colour.output;
  EXPECT_NE(colour.output.find("purple"), std::string::npos) << colour.output;
  auto seated = test::run_cli("phantom --scenario typing --chair grey --frames 2 --empty-frames 1 --out " +
                              (dir / "rec").string());
  ASSERT_EQ(seated.exit_code, 0) << seated.output;
  EXPECT_NE(test::read_file(dir / "rec" / "recording.json").find("chair=grey"), std::string::npos);
}

TEST(PhantomCli, MissingOutExitsTwo) {
  auto r = test::run_cli("phantom --scenario upright");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
}

TEST(PhantomCli, BadSubjectExitsOneNamingTheField) {
  test::TempDir dir;
  std::string text = test::read_file(test::source_path("config/subjects/generic.json"));
  text.replace(text.find("\"mass_kg\": 75"), 13, "\"mass_kg\": \"heavy\"");
  test::write_file(dir / "bad.json", text);
  auto r = test::run_cli("phantom --scenario upright --subject " + (dir / "bad.json").string() + " --out " +
                         (dir / "rec").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.json: mass_kg: expected a number"), std::string::npos) << r.output;
}

TEST(PhantomCli, UnwritableOutExitsOne) {
  test::TempDir dir;
  test::write_file(dir / "file", "x");
  auto r = test::run_cli("phantom --scenario upright --frames 2 --out " + (dir / "file" / "rec").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
}

// The station, scene and compression options reach the recording.
TEST(PhantomCli, StationSceneAndCompressionOptions) {
  test::TempDir dir;
  auto r = test::run_cli("phantom --scenario typing --frames 2 --empty-frames 1 --camera-tilt 20 --camera-roll 10 "
                         "--pair-angle 70 --heading 30 --room cluttered --h264 30 --out " + (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto rig = load_calibration(dir / "rec" / "calibration.yaml");
  ASSERT_TRUE(rig) << rig.error().message;
  const Eigen::Vector3d f = rig->frontal.R.row(2), l = rig->lateral.R.row(2);
  const Eigen::Vector2d fh(f.x(), f.z()), lh(l.x(), l.z());
  EXPECT_NEAR(std::acos(fh.normalized().dot(lh.normalized())) * 180 / M_PI, 70, 0.1);
  EXPECT_NEAR(std::asin(-f.y()) * 180 / M_PI, 20, 1e-6);
  const std::string json = test::read_file(dir / "rec" / "recording.json");
  for (const char* note : {"camera_tilt=20", "pair_angle=70", "heading=30", "room=cluttered", "furniture=desk", "h264_crf=30"})
    EXPECT_NE(json.find(note), std::string::npos) << note;
}

TEST(PhantomCli, CalibrationAndGeometryTogetherAreRefused) {
  test::TempDir dir;
  ASSERT_TRUE(save_calibration(dir / "calibration.yaml", CameraRig::default_rig()));
  auto r = test::run_cli("phantom --scenario upright --frames 2 --camera-tilt 10 --calibration " +
                         (dir / "calibration.yaml").string() + " --out " + (dir / "rec").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("give one or the other"), std::string::npos) << r.output;
  auto half = test::run_cli("phantom --scenario upright --frames 2 --backdrop-frontal " +
                            (dir / "calibration.yaml").string() + " --out " + (dir / "rec").string());
  EXPECT_EQ(half.exit_code, 2) << half.output;
  const std::string not_an_image = (dir / "calibration.yaml").string();
  auto unreadable = test::run_cli("phantom --scenario upright --frames 2 --backdrop-frontal " + not_an_image +
                                  " --backdrop-lateral " + not_an_image + " --out " + (dir / "rec").string());
  EXPECT_NE(unreadable.exit_code, 0) << unreadable.output;
  EXPECT_NE(unreadable.output.find(not_an_image + ": cannot read it as an image (give a PNG or JPEG photograph of the room)"),
            std::string::npos)
      << unreadable.output;
  auto out_of_range = test::run_cli("phantom --scenario upright --pair-angle 150 --out " + (dir / "rec").string());
  EXPECT_NE(out_of_range.exit_code, 0);
}

}  // namespace
}  // namespace spinewatch::phantom
