// A colour station end to end through the tools (issue 15, item 2):
// `spinewatch background` captures the empty scene of YUYV cameras in
// colour, a recording carrying it replays with its cast shadow not taken
// for the worker, and `shadow_ratio = 1` (shadows kept) shows the same
// recording as grey cameras see it.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "test_support.hpp"

namespace spinewatch {
namespace {

struct Scores {
  int lost = -1;
  double neck = 0, waist = 0, worst = 0;
};

Scores eval(const std::filesystem::path& rec, const std::filesystem::path& config) {
  auto r = test::run_cli("--log-level warn eval --recording '" + rec.string() + "' --config '" + config.string() + "' --json");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  return {j.at("lost_frames").get<int>(), j.at("neck").at("mean").get<double>(), j.at("waist").at("mean").get<double>(),
          std::max(j.at("neck").at("max").get<double>(), j.at("waist").at("max").get<double>())};
}

TEST(ColourStation, ItsCapturedBackgroundKeepsACastShadowOutOfTheSilhouette) {
  test::TempDir dir;
  // The installer's capture: an empty colour scene.
  auto r = test::run_cli("--log-level warn phantom --subject generic --colour --scenario upright --empty-frames 30 --frames 1 --out '" +
                         (dir / "empty").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli("background --recording '" + (dir / "empty").string() + "' --frames 30 --out '" +
                    (dir / "station").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("with colour"), std::string::npos) << r.output;
  for (const char* png : {"background_frontal.png", "background_lateral.png"}) {
    const cv::Mat image = cv::imread((dir / "station" / png).string(), cv::IMREAD_UNCHANGED);
    EXPECT_EQ(image.channels(), 3) << png;
  }
  // The worker in view from the first frame, with a lamp's shadow; the
  // recording carries the station's background, as `record` copies it.
  const auto rec = dir / "rec";
  r = test::run_cli("--log-level warn phantom --colour --shadow --scenario flexion --frames 60 --empty-frames 0 --subject '" +
                    test::source_path("config/subjects/tall.json").string() + "' --out '" + rec.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* png : {"background_frontal.png", "background_lateral.png"})
    std::filesystem::copy_file(dir / "station" / png, rec / png, std::filesystem::copy_options::overwrite_existing);
  // The phantom's named subjects carry the generic spine (docs/phantom.md).
  const std::string placement = "[subject]\nspine_placement = \"generic\"\n";
  test::write_file(dir / "colour.toml", placement);
  test::write_file(dir / "keep.toml", placement + "[silhouette]\nshadow_ratio = 1.0\n");
  const Scores colour = eval(rec, dir / "colour.toml");
  const Scores kept = eval(rec, dir / "keep.toml");
  EXPECT_EQ(colour.lost, 0);
  EXPECT_LT(colour.neck, 20.0);
  EXPECT_LT(colour.waist, 12.0);
  EXPECT_LT(colour.worst, 30.0);
  // With shadows kept as person, the shadow joins the silhouette (what grey
  // cameras see: 25–35 mm, docs/cvsm.md).
  EXPECT_GT(kept.waist, colour.waist + 15.0) << kept.neck << " / " << kept.waist;
}

}  // namespace
}  // namespace spinewatch
