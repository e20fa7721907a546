// Calibrating from live cameras: two fake V4L2 devices stream the phantom's
// rendered board — held at poses (each held for a few frames, as a person
// pauses), then placed — and the live session keeps one still view per
// pose, says how far it is, and hands calibrate_station what a recording
// would have given it.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <regex>

#include "spinewatch/calibrate/live_session.hpp"
#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/phantom/board_views.hpp"
#include "station_rig.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using namespace std::chrono_literals;

constexpr int kHold = 4;  // frames each pose is held (kept after 2 still ones)

// What both cameras show: the board at each pose for kHold frames, cycling;
// the placement board once `placed` is set (the installer placed it).
struct Scene {
  std::array<std::vector<cv::Mat>, 2> views, placement;
  std::atomic<bool> placed{false};
};

Scene* render_scene(const CameraRig& rig, const CalibrationBoard& board, int views_per_camera,
                    std::array<bool, 2> seen) {
  auto* scene = new Scene;
  phantom::BoardSessionOptions o;
  o.views_per_camera = views_per_camera;
  o.seed = 21;  // not a seed the accuracy tests use
  const phantom::BoardSession plan = phantom::plan_board_session(rig, board, o);
  std::vector<phantom::BoardPose> held;
  for (const auto& pose : plan.views)
    for (int k = 0; k < kHold; ++k) held.push_back(pose);
  auto views = phantom::render_board_views(rig, board, held, seen, o.seed, o.noise_sigma);
  auto placed = phantom::render_board_views(rig, board, std::vector<phantom::BoardPose>(6, plan.placement), seen,
                                            o.seed, o.noise_sigma, 5000);
  for (int v = 0; v < 2; ++v) {
    scene->views[v] = std::move(views.grey[v]);
    scene->placement[v] = std::move(placed.grey[v]);
  }
  return scene;
}

// A fake camera whose frames are the scene's, as YUYV.
std::unique_ptr<V4l2Camera> camera(Scene& scene, int view) {
  FakeV4l2Script script;
  script.path = view ? "/dev/video-lateral" : "/dev/video-frontal";
  script.content = [&scene, view](std::uint64_t seq, std::uint8_t* bytes, std::uint32_t bytesperline) {
    const auto& frames = scene.placed.load() ? scene.placement[view] : scene.views[view];
    const cv::Mat& grey = frames[seq % frames.size()];
    for (int y = 0; y < grey.rows; ++y) {
      std::uint8_t* row = bytes + std::size_t(y) * bytesperline;
      for (int x = 0; x < grey.cols; ++x) {
        row[2 * x] = grey.at<std::uint8_t>(y, x);
        row[2 * x + 1] = 128;
      }
    }
  };
  V4l2CameraOptions options;
  options.path = script.path;
  options.name = view ? "lateral" : "frontal";
  options.retry_initial = 1ms;
  options.retry_max = 4ms;
  return std::make_unique<V4l2Camera>(options, std::make_shared<FakeV4l2Device>(script));
}

double rotation_difference_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a * b.transpose()).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / std::numbers::pi;
}

TEST(LiveCalibration, KeepsOneStillViewPerPoseAndCalibrates) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  std::unique_ptr<Scene> scene(render_scene(rig, board, 12, {true, true}));
  auto frontal = camera(*scene, 0), lateral = camera(*scene, 1);
  ASSERT_TRUE(frontal->start().ok());
  ASSERT_TRUE(lateral->start().ok());
  LiveSessionOptions options;
  options.views = 10;
  options.placement_frames = 4;
  options.timeout = test::scaled(std::chrono::milliseconds(60s));
  std::vector<std::string> progress;
  bool asked = false;
  LiveSessionHooks hooks;
  hooks.progress = [&](const std::string& line) { progress.push_back(line); };
  hooks.before_placement = [&] {
    asked = true;
    scene->placed = true;
  };
  auto session = collect_live({frontal.get(), lateral.get()}, board, options, hooks);
  frontal->stop();
  lateral->stop();
  ASSERT_TRUE(session) << session.error().message;
  EXPECT_TRUE(asked);
  EXPECT_EQ(session->size, cv::Size(320, 240));
  for (int v = 0; v < 2; ++v) {
    EXPECT_EQ(session->frames[v].views.size(), 10u);
    EXPECT_EQ(session->frames[v].placement.size(), 4u);
  }
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.front(), "frontal: 0/10 views, lateral: 0/10");
  EXPECT_NE(std::find(progress.begin(), progress.end(), "frontal: 10/10 views, lateral: 10/10"), progress.end());
  EXPECT_EQ(progress.back(), "frontal: 4/4 placement frames, lateral: 4/4");
  // Counts only ever go up, one view at a time.
  for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_NE(progress[i], progress[i - 1]);

  // Every view kept is a different pose: no two alike.
  for (int v = 0; v < 2; ++v) {
    const auto& kept = session->frames[v].views;
    for (std::size_t a = 0; a < kept.size(); ++a)
      for (std::size_t b = a + 1; b < kept.size(); ++b)
        EXPECT_GE(ViewCollector::displacement(board.detect(kept[a]), board.detect(kept[b])), 12.0)
            << "camera " << v << ": views " << a << " and " << b;
  }

  // And they calibrate: 10 views a camera is fewer than the accuracy tests'
  // 40, so the bounds are looser than the issue's (those are
  // calibration_test's); what is under test here is that the live frames
  // are the right ones.
  const StationCalibration result =
      calibrate_station(board, session->frames, session->size, {Placement::Upright, 1100}, {});
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  const CameraModel* truth[2] = {&rig.frontal, &rig.lateral};
  const CameraModel* got[2] = {&result.rig.frontal, &result.rig.lateral};
  for (int v = 0; v < 2; ++v) {
    const double centre = (truth[v]->centre_in_world() - got[v]->centre_in_world()).norm();
    const double angle = rotation_difference_deg(truth[v]->R, got[v]->R);
    std::printf("%s: centre %.1f mm, rotation %.2f deg\n", v ? "lateral" : "frontal", centre, angle);
    EXPECT_LT(centre, 30.0);
    EXPECT_LT(angle, 1.0);
  }
}

TEST(LiveCalibration, ACameraThatNeverSeesTheBoardIsNamedWhenTimeRunsOut) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  std::unique_ptr<Scene> scene(render_scene(rig, board, 3, {true, false}));
  auto frontal = camera(*scene, 0), lateral = camera(*scene, 1);
  ASSERT_TRUE(frontal->start().ok());
  ASSERT_TRUE(lateral->start().ok());
  LiveSessionOptions options;
  options.views = 3;
  // Long enough for the frontal camera's three poses (twelve frames) even
  // in a sanitizer build (there the whole of KeepsOneStillViewPerPose…,
  // both cameras' poses and the calibration, takes 7 s); the lateral
  // camera's views never complete. The fake cameras stream as fast as they
  // are read, so the session works the whole time: 3 s, and 10 s under the
  // sanitizers rather than a scaled 3 s (30 s).
  options.timeout = std::max(std::chrono::milliseconds(3000),
                             std::chrono::duration_cast<std::chrono::milliseconds>(test::scaled(std::chrono::milliseconds(1000))));
  auto session = collect_live({frontal.get(), lateral.get()}, board, options, {});
  frontal->stop();
  lateral->stop();
  ASSERT_FALSE(session);
  const std::string& m = session.error().message;
  EXPECT_TRUE(std::regex_search(m, std::regex("^calibrate --live: the views were not complete after [0-9]+ s — "
                                              "frontal: 3/3 views \\(")))
      << m;
  EXPECT_NE(m.find("lateral: 0/3 views ("), std::string::npos) << m;
  EXPECT_NE(m.find(", board in 0, still in 0, 0 kept)"), std::string::npos) << m;
}

// The collector alone: a moving board is not kept, a still one is, and the
// same pose again is not.
TEST(ViewCollector, KeepsAStillBoardOnceAtEachPose) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  phantom::BoardSessionOptions o;
  o.views_per_camera = 2;
  o.seed = 22;
  const auto plan = phantom::plan_board_session(rig, board, o);
  const auto a = plan.views[0], b = plan.views[1];
  const auto frames = phantom::render_board_views(rig, board, {a, a, a, b, a, a, a}, {true, false}, 22, 2.0);
  const auto& f = frames.grey[0];
  ViewCollector collector(board, {});
  EXPECT_EQ(collector.offer(cv::Mat(240, 320, CV_8U, cv::Scalar(150))), FrameVerdict::NoBoard);
  EXPECT_EQ(collector.offer(f[0]), FrameVerdict::Moving);  // no frame before it to compare
  EXPECT_EQ(collector.offer(f[1]), FrameVerdict::Moving);  // still for one frame
  EXPECT_EQ(collector.offer(f[2]), FrameVerdict::Kept);    // still for two
  EXPECT_EQ(collector.offer(f[3]), FrameVerdict::Moving);  // another pose: moved
  EXPECT_EQ(collector.offer(f[4]), FrameVerdict::Moving);
  EXPECT_EQ(collector.offer(f[5]), FrameVerdict::Moving);
  EXPECT_EQ(collector.offer(f[6]), FrameVerdict::SamePose);
  EXPECT_EQ(collector.kept(), 1);
  EXPECT_EQ(collector.summary(), "8 frames, board in 7, still in 2, 1 kept");
}

}  // namespace
}  // namespace spinewatch
