#pragma once
// The first silhouettes measured in the world, not along the image's rows
// and columns: where the subject stands and how high the top of his head
// is, for any calibrated view (rolled, tilted down, at any angle to the
// other). Each silhouette's outline is carried by its camera's rays onto
// the vertical plane through the subject's axis that faces that camera, so
// "up" is the world's up however the image is turned (docs/cvsm.md,
// "Measuring along the world's vertical").
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// A silhouette's outline on the vertical plane through (axis.x, ·, axis.y)
// facing the camera: per outline pixel, the height (world y) and the
// horizontal offset across the plane, both in mm.
struct PlaneOutline {
  struct Point {
    double across = 0, y = 0;
  };
  std::vector<Point> points;
  Eigen::Vector3d origin{0, 0, 0};  // the axis at the floor
  Eigen::Vector3d across{0, 0, 0};  // unit, horizontal, in the plane
  double top_y = 0;                 // the outline's highest edge (half a pixel beyond the highest pixel)
  double bottom_y = 0;
  // The highest edge lies within a few pixels of the image's border: the
  // top of the head may be beyond it.
  bool top_cut = true;
};
PlaneOutline plane_outline(const CameraModel& camera, const BitMask& mask, const Eigen::Vector2d& axis);

// The trunk's centre on the plane: the median of the outline's mid-points
// across, over the heights between fractions `from` and `to` of the way
// down from the top to the bottom, in 10 mm bands. Nothing when no band
// holds both sides of the outline.
std::optional<Eigen::Vector3d> trunk_centre(const PlaneOutline& outline, double from, double to);

// The subject's vertical axis (x, z) where the two views' trunk centre
// lines meet: each centre line with its camera spans a vertical plane.
// Starts where the cameras' lines of sight cross (where the station is
// aimed) and measures again from each result, `rounds` times; stays where
// it is when the views do not determine it (no trunk, parallel planes).
Eigen::Vector2d subject_axis(const CameraRig& rig, const BitMask& frontal, const BitMask& lateral, int rounds = 2);

}  // namespace spinewatch::cvsm_detail
