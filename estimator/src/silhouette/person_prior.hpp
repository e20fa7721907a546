#pragma once
// Where a subject at the station's calibrated place can appear in a view:
// the image of a box around the world origin (docs/calibration.md: the
// origin is on the floor where the subject stands or sits), large enough
// for a standing or seated adult with arms at their sides. Bootstrapping
// predicts the empty scene inside it from around it.
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {

struct PersonBox {
  double x_min_mm = -250, x_max_mm = 650;  // posterior … anterior (a seated subject's knees)
  double y_max_mm = 1950;                  // floor … above a tall head
  double z_half_mm = 300;                  // shoulders and arms
};

// The box's convex image in a width × height view; empty (all clear) when
// the box is behind the camera.
BitMask person_prior(const CameraModel& camera, int width, int height, const PersonBox& box = {});

}  // namespace spinewatch
