// A silhouette turned so that the world's vertical runs down its columns
// (cvsm/upright_view.hpp): the roll read from the calibration, the turned
// mask against the model rendered through a level camera, the way back to
// the image, and a head cut by the turned image's border.
#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cvsm/upright_view.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

using cvsm_detail::image_roll;
using cvsm_detail::UprightView;

constexpr double kDeg = M_PI / 180.0;

// The camera turned about its own optical axis by `roll_deg` (the image
// turns the other way).
CameraModel rolled(CameraModel c, double roll_deg) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  c.R = turn * c.R;
  c.t = turn * c.t;
  return c;
}

// The camera looking down by `tilt_deg` (turned about its own x axis).
CameraModel tilted(CameraModel c, double tilt_deg) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(-tilt_deg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  c.R = turn * c.R;
  c.t = turn * c.t;
  return c;
}

TEST(UprightView, RollComesFromTheCalibration) {
  const CameraModel level = CameraRig::default_rig().frontal;
  EXPECT_DOUBLE_EQ(image_roll(level), 0.0);
  // Looking down keeps the rows level: no roll.
  EXPECT_NEAR(image_roll(tilted(level, 45)), 0.0, 1e-12);
  for (const double roll : {-25.0, 10.0, 25.0}) {
    EXPECT_NEAR(std::abs(image_roll(rolled(level, roll))), roll * kDeg * (roll < 0 ? -1 : 1), 1e-9) << roll;
    // Tilted and rolled: the roll about the optical axis is what is read.
    EXPECT_NEAR(std::abs(image_roll(rolled(tilted(level, 30), roll))), std::abs(roll) * kDeg, 1e-9) << roll;
  }
  // Its sign: the world's up, drawn in the image, leans to the side it says.
  const CameraModel r = rolled(level, 25);
  const auto low = r.project({0, 1000, 0}), high = r.project({0, 1400, 0});
  ASSERT_TRUE(low && high);
  const Eigen::Vector2d up = (*high - *low).normalized();
  EXPECT_NEAR(std::atan2(up.x(), -up.y()), image_roll(r), 1e-9);
}

TEST(UprightView, ALevelViewIsTheMaskItself) {
  const CameraRig rig = CameraRig::default_rig();
  const Views v = render(rig, other_subject(), CvsmPose{});
  const UprightView view(rig.frontal, v.frontal);
  EXPECT_TRUE(view.level());
  EXPECT_EQ(&view.mask(), &v.frontal);
  EXPECT_EQ(view.to_image({12.5, 34.25}), Eigen::Vector2d(12.5, 34.25));
  EXPECT_TRUE(view.on_image_border(0, 50));
  EXPECT_FALSE(view.on_image_border(1, 50));
}

// The turned view of a rolled camera's silhouette is the level camera's
// silhouette, shifted onto the larger canvas: the same rows and columns
// up to the nearest-pixel resampling.
TEST(UprightView, ARolledViewTurnsBackToTheLevelOne) {
  const CameraRig level = CameraRig::default_rig();
  const BodyModel subject = other_subject();
  const Views flat = render(level, subject, CvsmPose{});
  for (const double roll : {10.0, 25.0}) {
    const CameraRig r{rolled(level.frontal, roll), rolled(level.lateral, roll)};
    const Views turned = render(r, subject, CvsmPose{});
    const UprightView view(r.frontal, turned.frontal);
    ASSERT_FALSE(view.level());
    // Every canvas pixel mapped back to the image and from there to the
    // level image (the level camera sees the same ray turned back).
    std::int64_t agree = 0, differ = 0;
    double worst_shift = 0;  // how far the canvas is from the level image shifted
    std::optional<Eigen::Vector2d> shift;
    const BitMask& m = view.mask();
    for (int y = 0; y < m.height(); ++y)
      for (int x = 0; x < m.width(); ++x) {
        const Eigen::Vector2d image = view.to_image({x, y});
        const auto world = r.frontal.ray_through(image);
        const auto back = level.frontal.project(level.frontal.centre_in_world() + 2000 * world);
        if (!back) continue;
        // Upright: the canvas is the level image, shifted.
        if (!shift) shift = *back - Eigen::Vector2d(x, y);
        worst_shift = std::max(worst_shift, (*back - Eigen::Vector2d(x, y) - *shift).norm());
        const long lx = std::lround(back->x()), ly = std::lround(back->y());
        if (lx < 0 || ly < 0 || lx >= kW || ly >= kH) continue;
        const long ix = std::lround(image.x()), iy = std::lround(image.y());
        if (ix < 0 || iy < 0 || ix >= kW || iy >= kH) continue;  // not in the rolled image
        (m.get(x, y) == flat.frontal.get(static_cast<int>(lx), static_cast<int>(ly)) ? agree : differ)++;
      }
    EXPECT_LT(worst_shift, 1e-6) << roll;
    // The outline's pixels may fall either way (two resamplings).
    EXPECT_GT(agree, 30000) << roll;
    EXPECT_LT(differ, agree / 50) << roll;
  }
}

TEST(UprightView, AHeadCutByATurnedBorderIsOnIt) {
  // The principal point 100 rows higher: the head (its top about 78 rows
  // above the centre) runs out of the image's top, and turned by 25° that
  // border crosses the canvas at a slant.
  CameraRig rig{rolled(CameraRig::default_rig().frontal, 25), rolled(CameraRig::default_rig().lateral, 25)};
  rig.frontal.camera_matrix(1, 2) -= 100;
  const Views v = render(rig, other_subject(), CvsmPose{});
  const UprightView view(rig.frontal, v.frontal);
  const BitMask& m = view.mask();
  int top = -1;
  for (int y = 0; y < m.height() && top < 0; ++y)
    if (m.count_row(y) > 0) top = y;
  ASSERT_GE(top, 0);
  bool on_border = false;
  for (int x = 0; x < m.width(); ++x) on_border = on_border || (m.get(x, top) && view.on_image_border(x, top));
  EXPECT_TRUE(on_border);
}

}  // namespace
}  // namespace spinewatch
