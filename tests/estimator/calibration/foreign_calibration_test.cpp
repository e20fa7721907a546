// Calibrations from other tools (foreign_calibration.hpp): small
// hand-written files of each format, and caliscope's own files of the
// shared real footage (../shared/data/real/caliscope).
#include "spinewatch/estimator/calibration/foreign_calibration.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace spinewatch {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Two cameras 2.8 m apart, both looking at the point (0, 0, 2) m of the
// file's frame: A at the origin along +Z, B at (2, 0, 2) looking along −X.
constexpr const char* kCaliscope = R"(
[cameras.0]
cam_id = 0
rotation_count = 0
error = 0.5
ignore = false
size = [1280, 720]
matrix = [[900.0, 0.0, 640.0], [0.0, 905.0, 360.0], [0.0, 0.0, 1.0]]
distortions = [-0.1, 0.01, 0.001, -0.002, 0.0]
translation = [0.0, 0.0, 0.0]
rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]

[cameras.1]
cam_id = 1
rotation_count = 1
error = 0.25
ignore = false
size = [1280, 720]
matrix = [[700.0, 0.0, 630.0], [0.0, 700.0, 370.0], [0.0, 0.0, 1.0]]
distortions = [0.1, -0.2, 0.0, 0.0, 0.05]
translation = [-2.0, 0.0, 2.0]
rotation = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]

[cameras.2]
cam_id = 2
ignore = true
size = [640, 480]
matrix = [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]]
distortions = [0.0, 0.0, 0.0, 0.0, 0.0]
)";

Result<CameraArray> load_text(const test::TempDir& dir, const std::string& name, const std::string& text) {
  test::write_file(dir / name, text);
  return load_camera_array(dir / name);
}

TEST(ForeignCalibration, CaliscopeMetresBecomeMillimetresAndRotationIsWorldToCamera) {
  test::TempDir dir;
  auto array = load_text(dir, "camera_array.toml", kCaliscope);
  ASSERT_TRUE(array) << array.error().message;
  EXPECT_EQ(array->format, "caliscope");
  ASSERT_EQ(array->cameras.size(), 3u);
  const NamedCamera& b = array->cameras[1];
  EXPECT_EQ(b.id, "1");
  EXPECT_EQ(b.name, "cam_1");
  EXPECT_DOUBLE_EQ(b.rms_px, 0.25);
  EXPECT_EQ(b.rotation_count, 1);
  EXPECT_EQ(b.model.image_width, 1280);
  EXPECT_EQ(b.model.image_height, 720);
  EXPECT_DOUBLE_EQ(b.model.t.x(), -2000.0);
  // x_cam = R·X + t: camera 1's centre is −Rᵀt = (2, 0, 2) m.
  EXPECT_LT((b.model.centre_in_world() - Eigen::Vector3d(2000, 0, 2000)).norm(), 1e-9);
  // The point both look at lands on both principal points.
  const Eigen::Vector3d target(0, 0, 2000);
  for (const NamedCamera& cam : {array->cameras[0], array->cameras[1]}) {
    auto px = cam.model.project(target);
    ASSERT_TRUE(px);
    EXPECT_NEAR(px->x(), cam.model.camera_matrix(0, 2), 1e-9);
    EXPECT_NEAR(px->y(), cam.model.camera_matrix(1, 2), 1e-9);
  }
  EXPECT_TRUE(array->cameras[2].ignored);
  EXPECT_FALSE(array->cameras[2].has_extrinsics);
}

TEST(ForeignCalibration, SelectPairByIdOrNameAndClearErrors) {
  test::TempDir dir;
  auto array = load_text(dir, "camera_array.toml", kCaliscope);
  ASSERT_TRUE(array) << array.error().message;
  auto by_id = select_pair(*array, "1", "0");
  ASSERT_TRUE(by_id) << by_id.error().message;
  EXPECT_DOUBLE_EQ(by_id->frontal.camera_matrix(0, 0), 700.0);
  auto by_name = select_pair(*array, "cam_0", "cam_1");
  ASSERT_TRUE(by_name) << by_name.error().message;
  EXPECT_DOUBLE_EQ(by_name->frontal.camera_matrix(0, 0), 900.0);
  auto defaults = select_pair(*array, "", "");  // the first two usable
  ASSERT_TRUE(defaults) << defaults.error().message;
  EXPECT_DOUBLE_EQ(defaults->lateral.camera_matrix(0, 0), 700.0);

  auto missing = select_pair(*array, "cam_7", "0");
  ASSERT_FALSE(missing);
  EXPECT_TRUE(contains(missing.error().message, "no camera \"cam_7\"")) << missing.error().message;
  EXPECT_TRUE(contains(missing.error().message, "0 (cam_0), 1 (cam_1), 2 (cam_2) [ignored]"))
      << missing.error().message;
  auto ignored = select_pair(*array, "0", "2");
  ASSERT_FALSE(ignored);
  EXPECT_TRUE(contains(ignored.error().message, "ignore = true")) << ignored.error().message;
  auto same = select_pair(*array, "0", "cam_0");
  ASSERT_FALSE(same);
  EXPECT_TRUE(contains(same.error().message, "the same camera")) << same.error().message;
}

// anipose: Rodrigues rotation, names, units of the board.
std::string anipose_file(double baseline) {
  return fmt::format(R"([cam_0]
name = "left"
size = [ 640, 480,]
matrix = [ [ 500.0, 0.0, 320.0,], [ 0.0, 500.0, 240.0,], [ 0.0, 0.0, 1.0,],]
distortions = [ 0.0, 0.0, 0.0, 0.0, 0.0,]
rotation = [ 0.0, 0.0, 0.0,]
translation = [ 0.0, 0.0, 0.0,]

[cam_1]
name = "right"
size = [ 640, 480,]
matrix = [ [ 510.0, 0.0, 320.0,], [ 0.0, 510.0, 240.0,], [ 0.0, 0.0, 1.0,],]
distortions = [ 0.0, 0.0, 0.0, 0.0, 0.0,]
rotation = [ 0.0, -1.5707963267948966, 0.0,]
translation = [ {}, 0.0, 0.0,]

[metadata]
adjusted = true
error = 0.7
)",
                     baseline);
}

TEST(ForeignCalibration, AniposeRodriguesVectorsAndUnits) {
  test::TempDir dir;
  auto mm = load_text(dir, "calibration.toml", anipose_file(1500.0));
  ASSERT_TRUE(mm) << mm.error().message;
  EXPECT_EQ(mm->format, "anipose");
  ASSERT_EQ(mm->cameras.size(), 2u);
  EXPECT_EQ(mm->cameras[1].id, "cam_1");
  EXPECT_EQ(mm->cameras[1].name, "right");
  // The Rodrigues vector (0, −π/2, 0): −90° about Y.
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_LT((mm->cameras[1].model.R - expected).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(mm->cameras[1].model.t.x(), 1500.0);
  ASSERT_FALSE(mm->notes.empty());
  EXPECT_TRUE(contains(mm->notes[0], "millimetres"));
  auto by_name = select_pair(*mm, "right", "left");
  ASSERT_TRUE(by_name) << by_name.error().message;

  auto metres = load_text(dir, "calibration_m.toml", anipose_file(1.5));
  ASSERT_TRUE(metres) << metres.error().message;
  EXPECT_DOUBLE_EQ(metres->cameras[1].model.t.x(), 1500.0);
  EXPECT_TRUE(contains(metres->notes[0], "metres"));
}

TEST(ForeignCalibration, StationYamlAndOpenCvJson) {
  test::TempDir dir;
  CameraRig rig = CameraRig::default_rig();
  rig.frontal.dist_coeffs[0] = -0.05;
  rig.frontal.image_width = 320;
  rig.frontal.image_height = 240;
  ASSERT_TRUE(save_calibration(dir / "calibration.yaml", rig));
  auto yaml = load_camera_array(dir / "calibration.yaml");
  ASSERT_TRUE(yaml) << yaml.error().message;
  EXPECT_EQ(yaml->format, "opencv-yaml");
  auto pair = select_pair(*yaml, "", "");
  ASSERT_TRUE(pair) << pair.error().message;
  EXPECT_LT((pair->lateral.t - rig.lateral.t).norm(), 1e-9);
  EXPECT_DOUBLE_EQ(pair->frontal.dist_coeffs[0], -0.05);

  const std::string camera = R"({"camera_matrix": {"type_id": "opencv-matrix", "rows": 3, "cols": 3, "dt": "d",
      "data": [300.0, 0.0, 160.0, 0.0, 300.0, 120.0, 0.0, 0.0, 1.0]},
    "dist_coeffs": {"type_id": "opencv-matrix", "rows": 1, "cols": 5, "dt": "d", "data": [0.1, 0, 0, 0, 0]},
    "R": {"type_id": "opencv-matrix", "rows": 3, "cols": 3, "dt": "d", "data": [1, 0, 0, 0, 1, 0, 0, 0, 1]},
    "t": {"type_id": "opencv-matrix", "rows": 3, "cols": 1, "dt": "d", "data": [0, 0, 2000]},
    "image_width": 320, "image_height": 240})";
  auto json = load_text(dir, "calibration.json", "{\"frontal\": " + camera + ", \"lateral\": " + camera + "}");
  ASSERT_TRUE(json) << json.error().message;
  EXPECT_EQ(json->format, "opencv-json");
  EXPECT_DOUBLE_EQ(json->cameras[1].model.dist_coeffs[0], 0.1);
  EXPECT_DOUBLE_EQ(json->cameras[1].model.t.z(), 2000.0);
  EXPECT_EQ(json->cameras[1].model.image_height, 240);
}

TEST(ForeignCalibration, BadFilesNameTheFieldAndLine) {
  test::TempDir dir;
  std::string bad = kCaliscope;
  bad.replace(bad.find("matrix = [[700.0, 0.0, 630.0], "), std::string("matrix = [[700.0, 0.0, 630.0], ").size(),
              "matrix = [");
  auto r = load_text(dir, "camera_array.toml", bad);
  ASSERT_FALSE(r);
  EXPECT_TRUE(contains(r.error().message, ":19: cameras.1.matrix: expected 3 rows")) << r.error().message;

  std::string not_rotation = kCaliscope;
  not_rotation.replace(not_rotation.find("[[0.0, 0.0, 1.0]"), 16, "[[0.0, 0.0, 2.0]");
  auto r2 = load_text(dir, "camera_array2.toml", not_rotation);
  ASSERT_FALSE(r2);
  EXPECT_TRUE(contains(r2.error().message, "not a rotation matrix")) << r2.error().message;

  auto neither = load_text(dir, "notes.txt", "just words\n");
  ASSERT_FALSE(neither);
  EXPECT_TRUE(contains(neither.error().message, "Accepted: caliscope camera_array.toml")) << neither.error().message;
  auto none = load_camera_array(dir / "absent.toml");
  ASSERT_FALSE(none);
  EXPECT_TRUE(contains(none.error().message, "no such file"));
}

// caliscope's calibration of the shared footage: cam_0 and cam_1 of
// charuco_calibration stand about 1.1 m apart, 83° between their axes;
// the point where their axes pass closest projects inside both images.
TEST(ForeignCalibration, SharedCaliscopeSessionsAreConsistent) {
  const auto root = test::source_path("../shared/data/real/caliscope");
  if (!std::filesystem::exists(root)) GTEST_SKIP() << root << " is absent (the shared real footage)";
  for (const char* session : {"charuco_calibration", "4_cam_recording"}) {
    auto array = load_camera_array(root / session / "camera_array.toml");
    ASSERT_TRUE(array) << array.error().message;
    ASSERT_EQ(array->cameras.size(), 4u) << session;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = i + 1; j < 4; ++j) {
        const NamedCamera& a = array->cameras[i];
        const NamedCamera& b = array->cameras[j];
        const double baseline = (a.model.centre_in_world() - b.model.centre_in_world()).norm();
        EXPECT_GT(baseline, 300.0) << session << " " << a.id << "-" << b.id;
        EXPECT_LT(baseline, 1800.0) << session << " " << a.id << "-" << b.id;
      }
  }
  auto array = load_camera_array(root / "charuco_calibration" / "camera_array.toml");
  ASSERT_TRUE(array) << array.error().message;
  auto rig = select_pair(*array, "cam_0", "cam_1");
  ASSERT_TRUE(rig) << rig.error().message;
  const Eigen::Vector3d c0 = rig->frontal.centre_in_world(), c1 = rig->lateral.centre_in_world();
  EXPECT_NEAR((c0 - c1).norm(), 1132, 5);
  const Eigen::Vector3d d0 = rig->frontal.R.row(2).transpose(), d1 = rig->lateral.R.row(2).transpose();
  EXPECT_NEAR(std::acos(d0.dot(d1)) * 180 / std::numbers::pi, 83.0, 0.5);
  // Closest approach of the two axes.
  const Eigen::Vector3d w = c0 - c1;
  const double b = d0.dot(d1), d = d0.dot(w), e = d1.dot(w), den = 1 - b * b;
  const double s = (b * e - d) / den, u = (e - b * d) / den;
  const Eigen::Vector3d target = 0.5 * ((c0 + s * d0) + (c1 + u * d1));
  for (const CameraModel* cam : {&rig->frontal, &rig->lateral}) {
    EXPECT_GT(cam->to_camera(target).z(), 300.0);
    auto px = cam->project(target);
    ASSERT_TRUE(px);
    EXPECT_GT(px->x(), 0);
    EXPECT_LT(px->x(), cam->image_width);
    EXPECT_GT(px->y(), 0);
    EXPECT_LT(px->y(), cam->image_height);
  }
}

// A camera whose images are mirrored (caliscope's 4_cam_recording cam_1,
// calibrated on its images as filmed; docs/calibration.md, "A mirrored
// camera"): its images flipped left to right are exactly those of the
// camera with cx' = w − 1 − cx, p2' = −p2 and the first rows of R and t
// negated — a rotation with determinant −1, which the station's
// calibration file refuses, so such a camera is calibrated again from its
// flipped views (calibrate --mirror) rather than converted.
TEST(ForeignCalibration, AMirroredCamerasFlippedImagesNeedAnImproperRotation) {
  CameraModel filmed;
  filmed.camera_matrix << 703.958, 0, 626.005, 0, 706.235, 348.864, 0, 0, 1;
  filmed.dist_coeffs = {0.192148, -0.256426, 0.002802, -0.005232, 0.115382};
  filmed.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  filmed.t = Eigen::Vector3d(40, -120, 900);
  filmed.image_width = 1280;
  filmed.image_height = 720;
  CameraModel flipped = filmed;
  flipped.camera_matrix(0, 2) = filmed.image_width - 1 - filmed.camera_matrix(0, 2);
  flipped.dist_coeffs[3] = -filmed.dist_coeffs[3];
  const Eigen::Matrix3d S = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  flipped.R = S * filmed.R;
  flipped.t = S * filmed.t;
  int compared = 0;
  for (double x = -300; x <= 300; x += 150)
    for (double y = -200; y <= 200; y += 100)
      for (double z = -200; z <= 400; z += 200) {
        const auto a = filmed.project({x, y, z}), b = flipped.project({x, y, z});
        ASSERT_TRUE(a && b);
        EXPECT_NEAR(b->x(), filmed.image_width - 1 - a->x(), 1e-6);
        EXPECT_NEAR(b->y(), a->y(), 1e-6);
        ++compared;
      }
  EXPECT_EQ(compared, 100);
  EXPECT_NEAR(flipped.R.determinant(), -1.0, 1e-9);
  test::TempDir dir;
  const CameraRig rig{CameraRig::default_rig().frontal, flipped};
  ASSERT_TRUE(save_calibration(dir / "flipped.yaml", rig));
  auto loaded = load_calibration(dir / "flipped.yaml");
  ASSERT_FALSE(loaded);
  EXPECT_TRUE(contains(loaded.error().message, "not a rotation matrix")) << loaded.error().message;
  EXPECT_TRUE(contains(loaded.error().message, "det = -1")) << loaded.error().message;
}

}  // namespace
}  // namespace spinewatch
