#pragma once
// The station's geometry as an installer might have set it up
// (docs/phantom.md, "Station geometry"): two cameras the same distance
// from the subject's vertical axis, looking down at the trunk, rolled,
// at an angle to each other other than 90°.
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"

#include <optional>

namespace spinewatch::phantom {

// Where the default rig's cameras aim and how far they stand (horizontally)
// from the subject's vertical axis (the world Y axis).
inline constexpr double kAimHeightMm = 1100, kCameraDistanceMm = 2000;

struct StationGeometry {
  // Both cameras look down by this much (0–45°). Without a height, they are
  // raised until they look at the aim point again.
  std::optional<double> tilt_deg;
  // Both cameras turned about their optical axes (0–25°): the world's
  // verticals lean in the image by it, their tops to the image's left.
  double roll_deg = 0;
  // The horizontal angle between the two optical axes (45–135°): the
  // lateral camera at that azimuth from +X towards +Z on a circle round the
  // subject (90: on +Z, as the default rig), the frontal camera stays on +X.
  double pair_angle_deg = 90;
  // The cameras' height above the floor (300–3500 mm). Without a tilt,
  // they are tilted until they look at the aim point; with both, the
  // optical axes cross the subject's axis at height − 2000·tan(tilt), which
  // must lie between 300 and 1900 mm.
  std::optional<double> height_mm;
};

// The rig of that geometry, the default rig's intrinsics (f = 300 px,
// principal point (160, 120), no distortion). StationGeometry{} gives the
// default rig's poses.
Result<CameraRig> station_rig(const StationGeometry& geometry);

}  // namespace spinewatch::phantom
