// OpenCV's longer distortion models (4, 5, 8, 12, 14 coefficients) in the
// camera model, and calibration files written by OpenCV's own tools.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

// Coefficients a real lens might have, in OpenCV's order; the first n used.
constexpr std::array<double, 14> kLens = {-0.21, 0.05,  0.001, -0.0007, 0.01,  0.02, -0.004,
                                          0.001, 0.002, -0.001, 0.0015, 0.0003, 0.01, -0.008};

CameraModel lens_camera(int n) {
  CameraModel cam = CameraRig::default_rig().lateral;
  cam.camera_matrix(0, 0) = 310;
  for (int i = 0; i < n; ++i) cam.dist_coeffs[static_cast<std::size_t>(i)] = kLens[static_cast<std::size_t>(i)];
  return cam;
}

std::vector<cv::Point3d> world_points() {
  std::vector<cv::Point3d> world;
  for (int i = 0; i < 60; ++i) world.emplace_back(-500 + 17 * i, 300 + 23 * i, -350 + 11 * i);
  return world;
}

class DistortionModel : public ::testing::TestWithParam<int> {};

TEST_P(DistortionModel, ProjectionMatchesOpenCv) {
  const int n = GetParam();
  const CameraModel cam = lens_camera(n);
  cv::Mat K, R, rvec, t;
  cv::eigen2cv(cam.camera_matrix, K);
  cv::eigen2cv(cam.R, R);
  cv::eigen2cv(cam.t, t);
  cv::Rodrigues(R, rvec);
  const cv::Mat dist(1, n, CV_64F, const_cast<double*>(kLens.data()));
  const auto world = world_points();
  std::vector<cv::Point2d> expected;
  cv::projectPoints(world, rvec, t, K, dist, expected);
  for (std::size_t i = 0; i < world.size(); ++i) {
    auto p = cam.project({world[i].x, world[i].y, world[i].z});
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x(), expected[i].x, 1e-6) << n << " coefficients, point " << i;
    EXPECT_NEAR(p->y(), expected[i].y, 1e-6) << n << " coefficients, point " << i;
  }
}

TEST_P(DistortionModel, RayThroughInvertsTheProjection) {
  const CameraModel cam = lens_camera(GetParam());
  for (const auto& w : world_points()) {
    const Eigen::Vector3d world(w.x, w.y, w.z);
    const auto pixel = cam.project(world);
    ASSERT_TRUE(pixel);
    const Eigen::Vector3d expected = (world - cam.centre_in_world()).normalized();
    EXPECT_LT((cam.ray_through(*pixel) - expected).norm(), 1e-9);
  }
}

TEST_P(DistortionModel, NormalisedAgreesWithUndistortPoints) {
  const int n = GetParam();
  const CameraModel cam = lens_camera(n);
  cv::Mat K;
  cv::eigen2cv(cam.camera_matrix, K);
  const cv::Mat dist(1, n, CV_64F, const_cast<double*>(kLens.data()));
  std::vector<cv::Point2d> pixels, undistorted;
  for (int v = 10; v < 240; v += 40)
    for (int u = 10; u < 320; u += 40) pixels.emplace_back(u, v);
  // Many iterations: OpenCV's default five stop short of the exact inverse.
  cv::undistortPoints(pixels, undistorted, K, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const auto nrm = cam.normalised({pixels[i].x, pixels[i].y});
    ASSERT_TRUE(nrm);
    EXPECT_NEAR(nrm->x(), undistorted[i].x, 1e-7);
    EXPECT_NEAR(nrm->y(), undistorted[i].y, 1e-7);
  }
}

TEST_P(DistortionModel, SavedAndLoadedWithTheShortestLength) {
  const int n = GetParam();
  CameraRig rig = CameraRig::default_rig();
  rig.lateral = lens_camera(n);
  test::TempDir dir;
  ASSERT_TRUE(save_calibration(dir / "calibration.yaml", rig));
  auto loaded = load_calibration(dir / "calibration.yaml");
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_EQ(loaded->lateral.dist_coeffs, rig.lateral.dist_coeffs);
  EXPECT_EQ(loaded->lateral.distortion().size(), std::size_t(std::max(n, 5)));
  EXPECT_EQ(loaded->frontal.distortion().size(), 5u);  // the project's own files stay 1×5
}

INSTANTIATE_TEST_SUITE_P(OpenCvLengths, DistortionModel, ::testing::Values(4, 5, 8, 12, 14));

// A file as OpenCV's calibration sample (samples/cpp/calibration.cpp)
// writes it: one camera at the top level, with its own metadata.
void write_opencv_sample(const std::filesystem::path& path, const char* k_key, const char* d_key, int n,
                         const char* w_key = "image_width", int width = 320) {
  cv::FileStorage fs(path.string(), cv::FileStorage::WRITE);
  fs << "calibration_time" << "Wed 02 Dec 2026 07:00:00 UTC";
  fs << "nr_of_frames" << 20 << w_key << width << (std::string(w_key) == "image_Width" ? "image_Height" : "image_height")
     << 240;
  fs << "board_width" << 9 << "board_height" << 6 << "square_size" << 25.0 << "flags" << 0;
  fs << k_key << (cv::Mat_<double>(3, 3) << 301.5, 0, 161.2, 0, 300.8, 119.4, 0, 0, 1);
  fs << d_key << cv::Mat(n, 1, CV_64F, const_cast<double*>(kLens.data()));
  fs << "avg_reprojection_error" << 0.21;
}

TEST(OpenCvFiles, SampleIntrinsicsLoad) {
  test::TempDir dir;
  for (auto [k, d, n] : {std::tuple{"camera_matrix", "distortion_coefficients", 5},
                         std::tuple{"Camera_Matrix", "Distortion_Coefficients", 8},
                         std::tuple{"camera_matrix", "distortion_coefficients", 14}}) {
    write_opencv_sample(dir / "cam.yml", k, d, n);
    auto cam = load_intrinsics(dir / "cam.yml");
    ASSERT_TRUE(cam) << cam.error().message;
    EXPECT_DOUBLE_EQ(cam->camera_matrix(0, 0), 301.5);
    EXPECT_DOUBLE_EQ(cam->camera_matrix(1, 2), 119.4);
    for (int i = 0; i < n; ++i) EXPECT_DOUBLE_EQ(cam->dist_coeffs[static_cast<std::size_t>(i)], kLens[static_cast<std::size_t>(i)]);
    for (std::size_t i = static_cast<std::size_t>(n); i < kMaxDistortion; ++i) EXPECT_EQ(cam->dist_coeffs[i], 0.0);
    EXPECT_EQ(cam->image_width, 320);
    EXPECT_EQ(cam->image_height, 240);
  }
  // The tutorial's out_camera_data spells the size image_Width / image_Height; XML as well as YAML.
  write_opencv_sample(dir / "cam.xml", "Camera_Matrix", "Distortion_Coefficients", 5, "image_Width", 640);
  auto cam = load_intrinsics(dir / "cam.xml");
  ASSERT_TRUE(cam) << cam.error().message;
  EXPECT_EQ(cam->image_width, 640);  // XML only after a whole declaration: OpenCV 4.6's XML reader crashes on
  // a header as short as this (found by the calibration_yaml fuzzer).
  test::write_file(dir / "bad.xml", "<?xml e=");
  auto bad = load_intrinsics(dir / "bad.xml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("XML without a whole <?xml version=\"1.0\"?> declaration"), std::string::npos)
      << bad.error().message;
}

// Per camera node, the OpenCV keys load as the project's own do.
TEST(OpenCvFiles, StationFileWithOpenCvKeysLoads) {
  test::TempDir dir;
  const CameraRig rig = CameraRig::default_rig();
  {
    cv::FileStorage fs((dir / "calibration.yaml").string(), cv::FileStorage::WRITE);
    const char* k_keys[2] = {"Camera_Matrix", "camera_matrix"};
    const char* d_keys[2] = {"Distortion_Coefficients", "distortion_coefficients"};
    const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
    const char* names[2] = {"frontal", "lateral"};
    for (int i = 0; i < 2; ++i) {
      cv::Mat K, R, t;
      cv::eigen2cv(cams[i]->camera_matrix, K);
      cv::eigen2cv(cams[i]->R, R);
      cv::eigen2cv(cams[i]->t, t);
      fs << names[i] << "{" << k_keys[i] << K << d_keys[i] << cv::Mat(4, 1, CV_64F, const_cast<double*>(kLens.data()))
         << "R" << R << "t" << t << "image_width" << 320 << "image_height" << 240 << "}";
    }
  }
  auto loaded = load_calibration(dir / "calibration.yaml");
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_TRUE(loaded->frontal.camera_matrix.isApprox(rig.frontal.camera_matrix));
  EXPECT_DOUBLE_EQ(loaded->lateral.dist_coeffs[3], kLens[3]);
  EXPECT_EQ(loaded->lateral.dist_coeffs[4], 0.0);
  EXPECT_TRUE(check_image_size(*loaded, 320, 240));
  auto other = check_image_size(*loaded, 640, 480);
  ASSERT_FALSE(other);
  EXPECT_NE(other.error().message.find("frontal: calibrated at 320x240 (image_width, image_height) but the stream is "
                                       "640x480"),
            std::string::npos)
      << other.error().message;
}

TEST(OpenCvFiles, WhatCannotBeMappedIsNamed) {
  test::TempDir dir;
  write_opencv_sample(dir / "cam.yml", "camera_matrix", "distortion_coefficients", 5);
  // One camera's intrinsics are not a station's calibration.
  auto rig = load_calibration(dir / "cam.yml");
  ASSERT_FALSE(rig);
  EXPECT_NE(rig.error().message.find("cam.yml: one camera's intrinsics (camera_matrix at the top level)"),
            std::string::npos)
      << rig.error().message;
  EXPECT_NE(rig.error().message.find("--frontal-intrinsics"), std::string::npos);

  auto error_of = [&](const std::string& yaml) {
    test::write_file(dir / "bad.yml", "%YAML:1.0\n---\n" + yaml);
    auto r = load_intrinsics(dir / "bad.yml");
    EXPECT_FALSE(r);
    return r ? std::string() : r.error().message;
  };
  const std::string K = "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                        "   data: [300., 0., 160., 0., 300., 120., 0., 0., 1.]\n";
  const std::string D = "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                        "   data: [0., 0., 0., 0., 0.]\n";
  EXPECT_NE(error_of(K + D + "Camera_Matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                             "   data: [300., 0., 160., 0., 300., 120., 0., 0., 1.]\n")
                .find("bad.yml: camera_matrix: also given as Camera_Matrix; keep one"),
            std::string::npos);
  EXPECT_NE(error_of(K).find("bad.yml: dist_coeffs: missing"), std::string::npos) << error_of(K);
  EXPECT_NE(error_of(K + D + "distortion_model: equidistant\n").find("bad.yml: distortion_model: 'equidistant' cannot be "
                                                                    "mapped onto OpenCV's pinhole model"),
            std::string::npos);
  EXPECT_NE(error_of(K + D + "image_width: 320\n").find("bad.yml: image_width: given without image_height"),
            std::string::npos);
  EXPECT_NE(error_of(K + D + "image_width: 320\nimage_height: -2\n")
                .find("bad.yml: image_height: expected a positive whole number of pixels"),
            std::string::npos);
  EXPECT_NE(error_of("xi: 1.2\n" + K + D).find("bad.yml: xi: an omnidirectional"), std::string::npos);
}

}  // namespace
}  // namespace spinewatch
