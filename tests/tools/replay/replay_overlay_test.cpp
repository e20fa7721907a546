// spinewatch replay --overlay: the PNGs exist for every N-th pair, have the
// documented size, and show the silhouette outline on the silhouette's
// boundary and the vertebrae where the stream says they are.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/replay/overlay.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr int kWidth = 320, kHeight = 240, kScale = 2;

using test::read_ndjson;

bool is(const cv::Vec3b& px, const cv::Scalar& c) { return px[0] == c[0] && px[1] == c[1] && px[2] == c[2]; }

class ReplayOverlay : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    auto r = test::run_cli("phantom --subject generic --scenario flexion --frames 24 --seed 5 --out " + rec().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::run_cli("replay --recording " + rec().string() + " --out " + (dir_->path() / "p.ndjson").string() +
                      " --overlay " + (dir_->path() / "ovl").string() + " --every 3");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    lines_ = new std::vector<nlohmann::json>(read_ndjson(dir_->path() / "p.ndjson"));
  }
  static void TearDownTestSuite() {
    delete lines_;
    delete dir_;
  }
  static std::filesystem::path rec() { return dir_->path() / "rec"; }
  static std::filesystem::path png(std::uint64_t seq) {
    return dir_->path() / "ovl" / fmt::format("pair_{:06d}.png", seq);
  }
  // Luma of frame `index` of a view of the (YUYV) phantom recording.
  static cv::Mat luma(const std::string& view, std::size_t index) {
    const std::string raw = test::read_file(rec() / (view + ".raw"));
    const std::size_t bytes = kWidth * kHeight * 2;
    cv::Mat m(kHeight, kWidth, CV_8UC1);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(raw[index * bytes + (y * kWidth + x) * 2]);
    return m;
  }
  // The last pair written that the estimator tracked.
  static const nlohmann::json& last_tracked_written() {
    for (std::size_t i = lines_->size(); i-- > 0;)
      if (i % 3 == 0 && (*lines_)[i]["state"] == "tracking") return (*lines_)[i];
    ADD_FAILURE() << "no tracked pair among the overlays";
    return lines_->front();
  }
  static test::TempDir* dir_;
  static std::vector<nlohmann::json>* lines_;
};
test::TempDir* ReplayOverlay::dir_ = nullptr;
std::vector<nlohmann::json>* ReplayOverlay::lines_ = nullptr;

TEST_F(ReplayOverlay, EveryThirdPairOnePngOfTheDocumentedSize) {
  ASSERT_EQ(lines_->size(), 34u);  // 10 empty + 24 person frames
  std::set<std::string> expected, found;
  for (std::size_t i = 0; i < lines_->size(); i += 3)
    expected.insert(png((*lines_)[i]["seq"].get<std::uint64_t>()).filename().string());
  for (const auto& entry : std::filesystem::directory_iterator(dir_->path() / "ovl"))
    found.insert(entry.path().filename().string());
  EXPECT_EQ(found, expected);
  for (const auto& name : found) {
    const cv::Mat image = cv::imread((dir_->path() / "ovl" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;
    EXPECT_EQ(image.cols, 2 * kWidth * kScale) << name;
    EXPECT_EQ(image.rows, (kHeight + OverlayOptions{}.strip_height) * kScale) << name;
  }
}

// The outline runs along the boundary of the person's silhouette: computed
// here independently as |frame − empty scene| over the estimator's default
// threshold, then compared pixel by pixel.
TEST_F(ReplayOverlay, OutlineLiesOnTheSilhouetteBoundary) {
  const auto& line = last_tracked_written();
  const auto seq = line["seq"].get<std::size_t>();  // the phantom's seq is the frame index
  const cv::Mat image = cv::imread(png(seq).string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  for (int v = 0; v < 2; ++v) {
    const std::string view = v == 0 ? "frontal" : "lateral";
    cv::Mat diff, mask, eroded, boundary, near;
    cv::absdiff(luma(view, seq), luma(view, 0), diff);
    mask = diff > 28;
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::Mat());  // sensor-noise specks
    cv::erode(mask, eroded, cv::Mat());
    boundary = mask & ~eroded;
    cv::dilate(boundary, near, cv::getStructuringElement(cv::MORPH_RECT, {7, 7}));  // ±3 camera px
    int outline = 0, on_boundary = 0;
    for (int y = 0; y < kHeight * kScale; ++y)
      for (int x = 0; x < kWidth * kScale; ++x)
        if (is(image.at<cv::Vec3b>(y, v * kWidth * kScale + x), overlay_colour::kOutline)) {
          ++outline;
          on_boundary += near.at<std::uint8_t>(y / kScale, x / kScale) != 0;
        }
    EXPECT_GT(outline, 300) << view;
    EXPECT_GT(on_boundary, 0.95 * outline) << view << ": " << on_boundary << " of " << outline;
  }
}

// T1 and L5 from the NDJSON line, projected through the recording's rig,
// land on the vertebra colour, and every pixel of that colour belongs to
// one of the 17 projected body centres.
TEST_F(ReplayOverlay, VertebraeDrawnWhereTheStreamPutsThem) {
  const auto& line = last_tracked_written();
  const cv::Mat image = cv::imread(png(line["seq"].get<std::uint64_t>()).string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  auto rig = load_calibration(rec() / "calibration.yaml");
  ASSERT_TRUE(rig) << rig.error().message;
  for (int v = 0; v < 2; ++v) {
    std::vector<cv::Point2d> centres;
    for (const auto& vertebra : line["vertebrae"]) {
      const auto& c = vertebra["body_center"];
      const auto px = (v == 0 ? rig->frontal : rig->lateral)
                          .project(Eigen::Vector3d(c[0].get<double>(), c[1].get<double>(), c[2].get<double>()));
      ASSERT_TRUE(px);
      // Camera pixel centre u → the centre of its kScale block; the lateral view sits right of the frontal.
      centres.emplace_back(px->x() * kScale + 0.5 * (kScale - 1) + v * kWidth * kScale,
                           px->y() * kScale + 0.5 * (kScale - 1));
    }
    auto coloured = [&](int x, int y) {
      return x >= 0 && y >= 0 && x < image.cols && y < image.rows &&
             is(image.at<cv::Vec3b>(y, x), overlay_colour::kVertebra);
    };
    for (const std::size_t level : {std::size_t{0}, std::size_t{16}}) {
      const int x = static_cast<int>(std::lround(centres[level].x)), y = static_cast<int>(std::lround(centres[level].y));
      EXPECT_TRUE(coloured(x, y) || coloured(x + 1, y) || coloured(x, y + 1) || coloured(x + 1, y + 1))
          << "level " << level << " view " << v << " at " << centres[level];
    }
    int pixels = 0;
    for (int y = 0; y < kHeight * kScale; ++y)
      for (int x = v * kWidth * kScale; x < (v + 1) * kWidth * kScale; ++x) {
        if (!coloured(x, y)) continue;
        ++pixels;
        double nearest = 1e9;
        for (const auto& c : centres) nearest = std::min(nearest, std::hypot(x - c.x, y - c.y));
        EXPECT_LE(nearest, kScale + 2.0) << "view " << v << " pixel " << x << "," << y;
      }
    EXPECT_GT(pixels, 17 * 4) << "view " << v;
  }
}

TEST(ReplayOverlayErrors, EveryZeroIsAUsageError) {
  test::TempDir dir;
  auto r = test::run_cli("replay --recording " + dir.path().string() + " --out - --overlay " +
                         (dir / "o").string() + " --every 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--every"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "o"));
}

TEST(ReplayOverlayErrors, UncreatableDirectoryExitsOneNamingIt) {
  test::TempDir dir;
  test::write_file(dir / "file", "not a directory");
  auto r = test::run_cli("phantom --subject generic --scenario upright --frames 2 --empty-frames 2 --out " + (dir / "rec").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli("replay --recording " + (dir / "rec").string() + " --out " + (dir / "p.ndjson").string() +
                    " --overlay " + (dir / "file/ovl").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find((dir / "file/ovl").string()), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "p.ndjson"));
}

}  // namespace
}  // namespace spinewatch
