// Which views the intrinsics leave out (estimator/src/calibration,
// fit_intrinsics): a view far worse than the others — over 3× their median
// and over 0.3 px at 320 pixels wide, scaled with the width — is left out.
// A corner taken for its neighbour is off by a square at any resolution; the
// blur of a hand-held board is a fixed share of the image, so it is more
// pixels at a higher resolution and must not cost a sharp-enough view there.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>

#include "calibration/camera_views.hpp"

namespace spinewatch {
namespace {

using calibration_detail::Observation;

constexpr int kBlurred = 7;  // the view with extra noise on every corner
constexpr int kSwapped = 13;  // the view with one corner found a square away

// 20 views of the caliscope-sized board (4 × 5 squares of 54 mm) about a
// metre from a camera of `width` pixels (fx 0.7 of the width), spread over
// the image and tilted up to 30° each way; every corner with 0.1 px of
// noise (per axis, at any width), the blurred view with 0.6 px more, the
// swapped view with one corner moved by a square.
std::vector<Observation> views(const CalibrationBoard& board, int width) {
  const double f = 0.7 * width, cx = width / 2.0, cy = width * 9 / 32.0;
  const cv::Matx33d K(f, 0, cx, 0, f, cy, 0, 0, 1);
  const cv::Vec<double, 5> dist(-0.1, 0.05, 0, 0, 0);
  cv::RNG rng(34);
  std::vector<int> ids(static_cast<std::size_t>(board.corner_count()));
  for (int i = 0; i < board.corner_count(); ++i) ids[static_cast<std::size_t>(i)] = i;
  const cv::Point3f centre(float(board.centre().x()), float(board.centre().y()), 0.f);
  std::vector<cv::Point3f> object;
  for (const cv::Point3f& p : board.object_points(ids)) object.push_back(p - centre);
  std::vector<Observation> out;
  for (int v = 0; v < 20; ++v) {
    const double a = 2 * 3.14159265 * v / 20;
    const cv::Vec3d rvec(0.5 * std::sin(3 * a), 0.5 * std::cos(2 * a), 0.2 * std::sin(a));
    const cv::Vec3d tvec(350 * std::cos(a), 180 * std::sin(a), 1000 + 150 * std::sin(5 * a));
    Observation o{v, ids, {}};
    cv::projectPoints(object, rvec, tvec, K, dist, o.pixels);
    const double noise = v == kBlurred ? 0.6 : 0.1;
    for (cv::Point2f& p : o.pixels) p += cv::Point2f(float(rng.gaussian(noise)), float(rng.gaussian(noise)));
    if (v == kSwapped) o.pixels[4] = o.pixels[5];
    out.push_back(std::move(o));
  }
  return out;
}

const ViewError& view(const calibration_detail::IntrinsicsFit& fit, int frame) {
  for (const ViewError& e : fit.views)
    if (e.frame == frame) return e;
  throw std::runtime_error("no such view");
}

TEST(LeftOutViews, FloorScalesWithTheImageWidth) {
  auto board = CalibrationBoard::create(
      {.squares_x = 4, .squares_y = 5, .square_mm = 54, .marker_mm = 40.5, .dictionary = "DICT_4X4_1000"});
  ASSERT_TRUE(board) << board.error().message;
  for (int width : {320, 1280}) {
    SCOPED_TRACE(width);
    auto fit = calibration_detail::fit_intrinsics(*board, views(*board, width), {width, width * 9 / 16});
    ASSERT_TRUE(fit) << fit.error().message;
    // The corner a square away is left out at any width.
    EXPECT_TRUE(view(*fit, kSwapped).left_out) << view(*fit, kSwapped).rms_px;
    // The blurred view is far over 3× the median and between the floors
    // of the two widths (0.3 px and 1.2 px): left out at 320, kept at 1280.
    const ViewError& blurred = view(*fit, kBlurred);
    EXPECT_GT(blurred.rms_px, 0.4);
    EXPECT_LT(blurred.rms_px, 1.1);
    EXPECT_EQ(blurred.left_out, width == 320) << blurred.rms_px;
    for (const ViewError& e : fit->views) {
      if (e.frame != kBlurred && e.frame != kSwapped) {
        EXPECT_FALSE(e.left_out) << e.frame << ": " << e.rms_px;
      }
    }
  }
}

}  // namespace
}  // namespace spinewatch
