#include <gtest/gtest.h>

#include <filesystem>

#include <opencv2/calib3d.hpp>
#include <Eigen/Core>
#include <opencv2/core/eigen.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

TEST(DefaultRig, WorldAxesAppearWhereDocumented) {
  const CameraRig rig = CameraRig::default_rig();
  // A point at the rig centre height on the world Y axis is at the principal point.
  const Eigen::Vector3d centre(0, 1100, 0);
  EXPECT_TRUE(rig.frontal.project(centre)->isApprox(Eigen::Vector2d(160, 120)));
  EXPECT_TRUE(rig.lateral.project(centre)->isApprox(Eigen::Vector2d(160, 120)));
  // Up (+Y) is up in both images.
  EXPECT_LT(rig.frontal.project({0, 1500, 0})->y(), 120);
  EXPECT_LT(rig.lateral.project({0, 1500, 0})->y(), 120);
  // The subject's right (+Z) is on the frontal image's left, as in a mirror-free photo of a facing person.
  EXPECT_LT(rig.frontal.project({0, 1100, 200})->x(), 160);
  // Anterior (+X) is on the lateral image's right.
  EXPECT_GT(rig.lateral.project({200, 1100, 0})->x(), 160);
  // Scale: 300 px focal length at 2000 mm, 100 mm → 15 px.
  EXPECT_NEAR(rig.frontal.project({0, 1200, 0})->y(), 105.0, 1e-9);
  EXPECT_TRUE(rig.frontal.centre_in_world().isApprox(Eigen::Vector3d(2000, 1100, 0)));
  // Behind the camera: no projection.
  EXPECT_FALSE(rig.frontal.project({3000, 1100, 0}));
}

TEST(CameraModel, ProjectionMatchesOpenCvWithDistortion) {
  CameraModel cam = CameraRig::default_rig().lateral;
  cam.dist_coeffs = {-0.21, 0.05, 0.001, -0.0007, 0.01};
  cam.camera_matrix(0, 0) = 310;  // fx != fy, to exercise both
  cv::Mat K, R, t, rvec;
  cv::eigen2cv(cam.camera_matrix, K);
  cv::eigen2cv(cam.R, R);
  cv::eigen2cv(cam.t, t);
  cv::Rodrigues(R, rvec);
  cv::Mat dist(1, 5, CV_64F, cam.dist_coeffs.data());
  std::vector<cv::Point3d> world;
  for (int i = 0; i < 50; ++i) world.emplace_back(-400 + 17 * i, 300 + 23 * i, -300 + 11 * i);
  std::vector<cv::Point2d> expected;
  cv::projectPoints(world, rvec, t, K, dist, expected);
  for (std::size_t i = 0; i < world.size(); ++i) {
    auto p = cam.project({world[i].x, world[i].y, world[i].z});
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x(), expected[i].x, 1e-6);
    EXPECT_NEAR(p->y(), expected[i].y, 1e-6);
  }
}

TEST(Calibration, SaveLoadRoundTrip) {
  test::TempDir dir;
  CameraRig rig = CameraRig::default_rig();
  rig.frontal.dist_coeffs = {0.1, -0.02, 0, 0, 0.003};
  ASSERT_TRUE(save_calibration(dir / "calibration.yaml", rig).ok());
  auto loaded = load_calibration(dir / "calibration.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(loaded->frontal.camera_matrix.isApprox(rig.frontal.camera_matrix));
  EXPECT_EQ(loaded->frontal.dist_coeffs, rig.frontal.dist_coeffs);
  EXPECT_TRUE(loaded->lateral.R.isApprox(rig.lateral.R));
  EXPECT_TRUE(loaded->lateral.t.isApprox(rig.lateral.t));
}

class BadCalibration : public ::testing::Test {
 protected:
  std::string load_error(const std::string& yaml) {
    test::write_file(dir_ / "calibration.yaml", yaml);
    auto r = load_calibration(dir_ / "calibration.yaml");
    EXPECT_FALSE(r.ok());
    return r.ok() ? "" : r.error().message;
  }
  std::string camera(const std::string& name, const std::string& t = "[0., 1100., 2000.]",
                     const std::string& R = "[1., 0., 0., 0., -1., 0., 0., 0., -1.]") {
    return name + ":\n"
           "   camera_matrix: !!opencv-matrix\n      rows: 3\n      cols: 3\n      dt: d\n"
           "      data: [300., 0., 160., 0., 300., 120., 0., 0., 1.]\n"
           "   dist_coeffs: !!opencv-matrix\n      rows: 1\n      cols: 5\n      dt: d\n      data: [0., 0., 0., 0., 0.]\n"
           "   R: !!opencv-matrix\n      rows: 3\n      cols: 3\n      dt: d\n      data: " + R + "\n"
           "   t: !!opencv-matrix\n      rows: 3\n      cols: 1\n      dt: d\n      data: " + t + "\n";
  }
  test::TempDir dir_;
};

TEST_F(BadCalibration, WellFormedFileLoads) {
  test::write_file(dir_ / "calibration.yaml", "%YAML:1.0\n---\n" + camera("frontal") + camera("lateral"));
  auto r = load_calibration(dir_ / "calibration.yaml");
  EXPECT_TRUE(r.ok()) << r.error().message;
}

TEST_F(BadCalibration, MissingCamera) {
  const auto msg = load_error("%YAML:1.0\n---\n" + camera("frontal"));
  EXPECT_NE(msg.find("lateral: missing camera node"), std::string::npos) << msg;
}

TEST_F(BadCalibration, DataDoesNotFillTheMatrix) {
  const auto msg = load_error("%YAML:1.0\n---\n" + camera("frontal", "[0., 1100.]") + camera("lateral"));
  EXPECT_NE(msg.find("calibration.yaml: frontal.t: not a matrix"), std::string::npos) << msg;
}

TEST_F(BadCalibration, WrongMatrixSize) {
  std::string lateral = camera("lateral");
  const std::string five = "cols: 5\n      dt: d\n      data: [0., 0., 0., 0., 0.]";
  lateral.replace(lateral.find(five), five.size(), "cols: 6\n      dt: d\n      data: [0., 0., 0., 0., 0., 0.]");
  const auto msg = load_error("%YAML:1.0\n---\n" + camera("frontal") + lateral);
  EXPECT_NE(msg.find("lateral.dist_coeffs: 6 coefficients; OpenCV's models have 4, 5, 8, 12 or 14"), std::string::npos)
      << msg;
  const std::string frontal =
      "frontal:\n"
      "   camera_matrix: !!opencv-matrix\n      rows: 2\n      cols: 3\n      dt: d\n"
      "      data: [300., 0., 160., 0., 300., 120.]\n";
  const auto msg2 = load_error("%YAML:1.0\n---\n" + frontal + camera("lateral"));
  EXPECT_NE(msg2.find("frontal.camera_matrix: expected 3x3, got 2x3"), std::string::npos) << msg2;
}

TEST_F(BadCalibration, NotARotation) {
  const auto msg = load_error("%YAML:1.0\n---\n" + camera("frontal") +
                              camera("lateral", "[0., 1100., 2000.]", "[2., 0., 0., 0., 1., 0., 0., 0., 1.]"));
  EXPECT_NE(msg.find("lateral.R: not a rotation matrix"), std::string::npos) << msg;
}

// Found by the calibration_yaml fuzzer (tests/fuzz): OpenCV sized the
// matrix from a corrupt header before reading its data and asked for
// 48 GB. The header is checked first now.
TEST_F(BadCalibration, AHeaderAskingForAHugeMatrixIsAnErrorNotAnAllocation) {
  for (const std::string cols : {"cols: 2147483647", "cols: -3", "cols: 3.5"}) {
    std::string frontal = camera("frontal");
    frontal.replace(frontal.find("cols: 3"), 7, cols);
    const auto msg = load_error("%YAML:1.0\n---\n" + frontal + camera("lateral"));
    EXPECT_NE(msg.find("calibration.yaml: frontal.camera_matrix: not a matrix (rows and cols must be integers 1..16)"),
              std::string::npos)
        << cols << ": " << msg;
  }
  // The fuzzer's own header is no line OpenCV writes: refused before it reads.
  std::string frontal = camera("frontal");
  frontal.replace(frontal.find("cols: 3"), 7, "cols:ols: 3");
  const auto msg = load_error("%YAML:1.0\n---\n" + frontal + camera("lateral"));
  EXPECT_NE(msg.find("calibration.yaml: line 6: \"      cols:ols: 3\": not a line of OpenCV's YAML"), std::string::npos)
      << msg;
}

// Found by the calibration_yaml fuzzer: this file made OpenCV's reader
// throw std::length_error, which was not caught and ended the program.
// Its line 21 is no line OpenCV writes, so it is refused before OpenCV
// reads it (the handler for OpenCV's exceptions stays behind that check).
TEST_F(BadCalibration, AFileThatMakesOpenCvThrowAStandardExceptionIsAnError) {
  const auto msg = load_error(
      test::read_file(test::source_path("tests/fuzz/corpus/calibration_yaml/regression-length-error-terminates.yaml")));
  EXPECT_NE(msg.find("calibration.yaml: line 21: "), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
}

// Found by the calibration_yaml fuzzer: a file whose root is not a map
// made OpenCV throw from fs["frontal"], outside any handler: terminate.
TEST_F(BadCalibration, ARootThatIsNotAMapIsAnError) {
  EXPECT_NE(load_error(test::read_file(
                test::source_path("tests/fuzz/corpus/calibration_yaml/regression-root-not-a-map-terminates.yaml")))
                .find("calibration.yaml: "),
            std::string::npos);
  // A block sequence is no line OpenCV writes for a calibration.
  EXPECT_NE(load_error("%YAML:1.0\n---\n- 1\n- 2\n").find("calibration.yaml: line 3: \"- 1\": not a line of OpenCV's YAML"),
            std::string::npos);
}

// Found by the calibration_yaml fuzzer (timeouts): OpenCV 4.6's YAML
// reader never returned on these files. Each is refused, naming its first
// line that is not one of the forms OpenCV writes, before OpenCV reads it;
// the first two at their stray dashes.
TEST_F(BadCalibration, ALineOpenCvWouldLoopOnIsRefusedFirst) {
  const auto corpus = test::source_path("tests/fuzz/corpus/calibration_yaml");
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("regression-opencv-never-returns", 0) != 0) continue;
    ++files;
    const auto msg = load_error(test::read_file(entry.path()));
    EXPECT_NE(msg.find("calibration.yaml: line "), std::string::npos) << name << ": " << msg;
    const bool stray_dashes_first = name == "regression-opencv-never-returns.yaml" ||
                                    name == "regression-opencv-never-returns-2.yaml";
    if (stray_dashes_first) {
      EXPECT_NE(msg.find("\"--\" only in a \"---\" document marker on a line of its own"), std::string::npos)
          << name << ": " << msg;
    }
  }
  EXPECT_EQ(files, 15);  // docs/testing.md, findings 7 and 11
  // And the lines of a calibration as OpenCV and its samples write them pass.
  const std::string wrapped =
      "%YAML:1.0\n---\n# a comment\ncalibration_time: \"Wed 04 Mar 2020 10:02:16 AM CET\"\nimage_width: 320\n"
      "image_height: 240\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 3.0000000000000000e+02, 0., 1.6000000000000000e+02, 0.,\n"
      "       300., 1.2e+02, 0., 0., 1. ]\ndistortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n"
      "   dt: d\n   data: [ -1.5e-01, .5, 0., 0., -.Inf ]\n";
  EXPECT_EQ(load_error(wrapped).find("calibration.yaml: line "), std::string::npos) << load_error(wrapped);
}

// Found by the calibration_yaml fuzzer: OpenCV 4.6's XML reader
// dereferences null on a truncated header (SIGSEGV). calibration.yaml is
// YAML; XML and JSON storage and NUL bytes are refused before OpenCV reads.
TEST_F(BadCalibration, XmlJsonAndNulBytesAreRefusedBeforeOpenCvReads) {
  EXPECT_NE(load_error(test::read_file(test::source_path(
                "tests/fuzz/corpus/calibration_yaml/regression-opencv-xml-null-dereference.yaml")))
                .find("calibration.yaml: XML or JSON storage; calibration.yaml is read as YAML only"),
            std::string::npos);
  EXPECT_NE(load_error("<?xml e=").find("XML or JSON storage"), std::string::npos);
  EXPECT_NE(load_error("  {\"frontal\": {}}").find("XML or JSON storage"), std::string::npos);
  EXPECT_NE(load_error(std::string("%YAML:1.0\n---\nfrontal: \0\n", 25)).find("calibration.yaml: a NUL byte: not a text file"),
            std::string::npos);
}

TEST_F(BadCalibration, NotYaml) {
  const auto msg = load_error("this is not: [a calibration\n");
  EXPECT_NE(msg.find("calibration.yaml"), std::string::npos) << msg;
}

TEST(Calibration, MissingFile) {
  auto r = load_calibration("/nonexistent/calibration.yaml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "/nonexistent/calibration.yaml: no such file");
}

}  // namespace
}  // namespace spinewatch
