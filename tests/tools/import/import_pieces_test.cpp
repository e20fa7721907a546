// The pieces of spinewatch import on synthetic data: the crop's camera
// model, OpenCV's resize convention it relies on, the colour conversion
// against its reference, and the world frame.
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/calibration/foreign_calibration.hpp"
#include "spinewatch/import/crop.hpp"
#include "spinewatch/import/world_frame.hpp"
#include "spinewatch/import/yuyv.hpp"

namespace spinewatch::import {
namespace {

CameraModel webcam() {
  CameraModel cam;
  cam.camera_matrix << 903.55, 0.0, 618.31, 0.0, 907.88, 394.21, 0.0, 0.0, 1.0;
  cam.dist_coeffs = {-0.332, 0.0464, -0.0043, 0.0041, 0.0666};
  cam.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, -0.3).normalized()).toRotationMatrix();
  cam.t = Eigen::Vector3d(120, -200, 1800);
  cam.image_width = 1280;
  cam.image_height = 720;
  return cam;
}

// A point projected through the original camera, its pixel mapped through
// the crop and scale, lands where the cropped camera projects it.
TEST(ImportCrop, CroppedCameraProjectsWhereTheMappedPixelIs) {
  const CameraModel cam = webcam();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const CropRect& crop : {CropRect{320, 120, 640, 480}, CropRect{160, 0, 960, 720}, CropRect{417, 233, 484, 363}}) {
    const CameraModel cropped = crop_camera(cam, crop);
    EXPECT_EQ(cropped.image_width, 320);
    double worst = 0;
    for (int i = 0; i < 200; ++i) {
      // Points in front of the camera, across its view.
      const Eigen::Vector3d in_camera(600 * u(rng), 350 * u(rng), 1500 + 500 * u(rng));
      const Eigen::Vector3d world = cam.R.transpose() * (in_camera - cam.t);
      auto original = cam.project(world);
      auto imported = cropped.project(world);
      ASSERT_TRUE(original && imported);
      const Eigen::Vector2d mapped(crop_x(original->x(), crop), crop_y(original->y(), crop));
      worst = std::max(worst, (mapped - *imported).norm());
    }
    EXPECT_LT(worst, 0.01) << crop.describe();
  }
}

// The pixel-centre map the crop's camera assumes is what cv::resize does
// (INTER_AREA, as the import scales): a small bright blob's centroid moves
// as x' = (x − x0 + 0.5)·s − 0.5.
TEST(ImportCrop, ResizeFollowsThePixelCentreMap) {
  for (const CropRect& crop : {CropRect{100, 40, 640, 480}, CropRect{52, 10, 960, 720}, CropRect{0, 0, 484, 363}}) {
    cv::Mat image(760, 1100, CV_32F, cv::Scalar(0));
    const double bx = crop.x + 0.37 * crop.width + 0.3, by = crop.y + 0.61 * crop.height + 0.7;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x)
        image.at<float>(y, x) = static_cast<float>(std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / (2 * 36.0)));
    cv::Mat out;
    cv::resize(image(cv::Rect(crop.x, crop.y, crop.width, crop.height)), out, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    double sx = 0, sy = 0, sum = 0;
    for (int y = 0; y < out.rows; ++y)
      for (int x = 0; x < out.cols; ++x) {
        const double v = out.at<float>(y, x);
        sx += v * x;
        sy += v * y;
        sum += v;
      }
    EXPECT_NEAR(sx / sum, crop_x(bx, crop), 0.01) << crop.describe();
    EXPECT_NEAR(sy / sum, crop_y(by, crop), 0.01) << crop.describe();
  }
}

TEST(ImportCrop, ParsedAndChosenCropsAreFourByThreeInsideTheFrame) {
  auto ok = parse_crop("320,120,640,480", 1280, 720);
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_DOUBLE_EQ(ok->scale(), 0.5);
  for (const char* bad : {"320,120,640,400", "800,120,640,480", "1,2,3", "a,b,c,d", "0,0,642,481"}) {
    auto r = parse_crop(bad, 1280, 720);
    EXPECT_FALSE(r) << bad;
  }
  // A box near the right edge: the crop holds it, inside the frame.
  const CropRect c = crop_around(1000, 200, 200, 400, 1280, 720, 0.1, 640);
  EXPECT_TRUE(check_crop(c, 1280, 720)) << c.describe();
  EXPECT_LE(c.x, 1000);
  EXPECT_GE(c.x + c.width, 1200);
  EXPECT_LE(c.y, 200);
  EXPECT_GE(c.y + c.height, 600);
  // Larger than the frame allows: the largest 4:3.
  const CropRect all = crop_around(0, 0, 1280, 720, 1280, 720, 0.1, 640);
  EXPECT_EQ(all.width, 960);
  EXPECT_EQ(all.height, 720);
}

TEST(ImportYuyv, FastConversionMatchesTheBt601Reference) {
  cv::Mat bgr(37, 64, CV_8UC3);
  cv::randu(bgr, cv::Scalar::all(0), cv::Scalar::all(256));
  std::vector<std::uint8_t> fast, reference;
  bgr_to_yuyv(bgr, fast);
  bgr_to_yuyv_reference(bgr, reference);
  ASSERT_EQ(fast.size(), reference.size());
  int worst = 0;
  for (std::size_t i = 0; i < fast.size(); ++i) worst = std::max(worst, std::abs(fast[i] - reference[i]));
  EXPECT_LE(worst, 1);
  // Grey stays grey: U = V = 128.
  cv::Mat grey(2, 2, CV_8UC3, cv::Scalar(90, 90, 90));
  bgr_to_yuyv(grey, fast);
  EXPECT_EQ(fast[0], 90);
  EXPECT_EQ(fast[1], 128);
  EXPECT_EQ(fast[3], 128);
}

// A camera at `centre` looking at `target`, image "up" towards `up`.
CameraModel looking(const Eigen::Vector3d& centre, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  CameraModel cam = webcam();
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();  // image right
  const Eigen::Vector3d y = z.cross(x);                // image down
  cam.R.row(0) = x.transpose();
  cam.R.row(1) = y.transpose();
  cam.R.row(2) = z.transpose();
  cam.t = -cam.R * centre;
  return cam;
}

// A file frame with Z up (as caliscope's board on the floor gives): the
// station's frame has Y up, X towards the frontal camera, the lateral one
// on +Z, and every camera still sees every point where it did.
TEST(ImportWorldFrame, ZUpFileBecomesTheStationFrame) {
  const Eigen::Vector3d up(0, 0, 1), target(500, 300, 800);
  const CameraRig rig{looking({2500, 300, 1200}, target, up), looking({500, -1700, 1100}, target, up)};
  auto frame = choose_world_frame(rig, up, 1100);
  ASSERT_TRUE(frame) << frame.error().message;
  const CameraModel f = frame->to_station(rig.frontal), l = frame->to_station(rig.lateral);
  const Eigen::Vector3d cf = f.centre_in_world(), cl = l.centre_in_world();
  EXPECT_GT(cf.x(), 1500);
  EXPECT_NEAR(cf.z(), 0, 1e-6);
  EXPECT_GT(cl.z(), 1500);  // the lateral camera on the subject's right
  EXPECT_NEAR(0.5 * (cf.y() + cl.y()), 1100, 1e-6);  // --camera-height
  // The origin lies on the vertical through the look-at point.
  const Eigen::Vector3d target_station = frame->to_station(target);
  EXPECT_NEAR(target_station.x(), 0, 1e-6);
  EXPECT_NEAR(target_station.z(), 0, 1e-6);
  // Same pixels.
  for (const Eigen::Vector3d& p : {target, Eigen::Vector3d(700, 100, 1000), Eigen::Vector3d(300, 500, 400)}) {
    EXPECT_LT((*rig.frontal.project(p) - *f.project(frame->to_station(p))).norm(), 1e-9);
    EXPECT_LT((*rig.lateral.project(p) - *l.project(frame->to_station(p))).norm(), 1e-9);
  }
  EXPECT_GT(f.R.determinant(), 0.999);
}

// Cameras looking down: their image "up"s lean towards where they look,
// their image horizontals stay level — up is perpendicular to those.
TEST(ImportWorldFrame, UpEstimatedFromUprightImagesIncludingTurnedCameras) {
  const Eigen::Vector3d up(0, 0, 1), target(0, 0, 800);
  CameraArray array;
  array.format = "caliscope";
  NamedCamera a, b;
  a.id = "0";
  a.model = looking({2000, 0, 1300}, target, up);
  b.id = "1";
  // Mounted on its side: the image's "up" is the camera's −x; caliscope
  // turns its image 90° clockwise for display (rotation_count 1).
  b.model = looking({0, -2000, 1200}, target, Eigen::Vector3d(1, 0, 0));
  b.rotation_count = 1;
  array.cameras = {a, b};
  std::vector<std::string> report;
  auto estimated = estimate_up(array, report);
  ASSERT_TRUE(estimated) << estimated.error().message;
  EXPECT_GT(estimated->dot(up), 0.9999) << estimated->transpose();  // both look down 12–14°
  ASSERT_EQ(report.size(), 1u);
  EXPECT_NE(report[0].find("perpendicular to the image horizontals of 2 cameras"), std::string::npos) << report[0];

  auto given = parse_up("0, 0, 2");
  ASSERT_TRUE(given) << given.error().message;
  EXPECT_NEAR(given->z(), 1.0, 1e-12);
  EXPECT_FALSE(parse_up("0,0,0"));
  EXPECT_FALSE(parse_up("up"));
}

}  // namespace
}  // namespace spinewatch::import
