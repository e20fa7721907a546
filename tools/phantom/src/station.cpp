#include "spinewatch/phantom/station.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "spinewatch/estimator/units.hpp"

namespace spinewatch::phantom {
namespace {


// A camera `kCameraDistanceMm` from the Y axis at azimuth `azimuth_deg`
// (0: on +X), `height_mm` up, looking towards the axis and down by
// `tilt_deg`, rolled by `roll_deg`.
CameraModel camera_at(double azimuth_deg, double height_mm, double tilt_deg, double roll_deg) {
  CameraModel camera = CameraRig::default_rig().frontal;  // the intrinsics
  const Eigen::Vector3d towards(-std::cos(azimuth_deg * kRadPerDeg), 0, -std::sin(azimuth_deg * kRadPerDeg));
  const Eigen::Vector3d axis = std::cos(tilt_deg * kRadPerDeg) * towards - std::sin(tilt_deg * kRadPerDeg) * Eigen::Vector3d::UnitY();
  // Image down: the world's down, less its part along the axis.
  const Eigen::Vector3d down = (-Eigen::Vector3d::UnitY() - (-axis.y()) * axis).normalized();
  const Eigen::Vector3d right = down.cross(axis);
  const double c = std::cos(roll_deg * kRadPerDeg), s = std::sin(roll_deg * kRadPerDeg);
  camera.R.row(0) = (c * right + s * down).transpose();
  camera.R.row(1) = (-s * right + c * down).transpose();
  camera.R.row(2) = axis.transpose();
  const Eigen::Vector3d centre(-kCameraDistanceMm * towards.x(), height_mm, -kCameraDistanceMm * towards.z());
  camera.t = -camera.R * centre;
  return camera;
}

}  // namespace

Result<CameraRig> station_rig(const StationGeometry& g) {
  const auto out_of = [](const char* what, double v, double lo, double hi) {
    return Error{fmt::format("{}: {} is out of range [{}, {}]", what, v, lo, hi)};
  };
  if (g.tilt_deg && !(*g.tilt_deg >= 0 && *g.tilt_deg <= 45)) return out_of("camera tilt", *g.tilt_deg, 0, 45);
  if (!(g.roll_deg >= 0 && g.roll_deg <= 25)) return out_of("camera roll", g.roll_deg, 0, 25);
  if (!(g.pair_angle_deg >= 45 && g.pair_angle_deg <= 135)) return out_of("pair angle", g.pair_angle_deg, 45, 135);
  if (g.height_mm && !(*g.height_mm >= 300 && *g.height_mm <= 3500)) return out_of("camera height", *g.height_mm, 300, 3500);

  double tilt = g.tilt_deg.value_or(0), height = kAimHeightMm;
  if (g.tilt_deg && g.height_mm) {
    height = *g.height_mm;
    const double aim = height - kCameraDistanceMm * std::tan(tilt * kRadPerDeg);
    if (aim < 300 || aim > 1900)
      return Error{fmt::format("camera height {} mm with tilt {}°: the cameras would look at {:.0f} mm above the floor, "
                               "not at the subject's trunk (300–1900 mm); give one of them, or a steeper/shallower tilt",
                               height, tilt, aim)};
  } else if (g.tilt_deg) {
    height = kAimHeightMm + kCameraDistanceMm * std::tan(tilt * kRadPerDeg);
  } else if (g.height_mm) {
    height = *g.height_mm;
    tilt = std::atan((height - kAimHeightMm) / kCameraDistanceMm) / kRadPerDeg;
  }
  CameraRig rig;
  rig.frontal = camera_at(0, height, tilt, g.roll_deg);
  rig.lateral = camera_at(g.pair_angle_deg, height, tilt, g.roll_deg);
  return rig;
}

}  // namespace spinewatch::phantom
