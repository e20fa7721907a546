#pragma once
// What no real station looks like (docs/calibration.md, "The report and
// its refusals"): the rules `spinewatch calibrate` refuses a calibration
// by and `spinewatch check` refuses a calibration file by — the same
// rules, so that a file check passes is one calibrate could have written.
#include <string>
#include <vector>

#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch {

struct RigRules {
  bool free_aspect = false;          // --aspect free: fy/fx may be anything (anamorphic lenses, non-square pixels)
  double max_aspect_error = 0.05;    // |fy/fx − 1|
  double min_distance_mm = 300;      // between the cameras' centres
  double min_axis_angle_deg = 20;    // between the optical axes
};

// One camera's intrinsics: fy/fx within max_aspect_error of 1, the
// principal point inside the central third of the image (when the image
// size is known). Each problem names the camera and what to do.
std::vector<std::string> intrinsics_problems(const std::string& name, const CameraModel& camera,
                                             const RigRules& rules);

// The two cameras' extrinsics: their centres at least min_distance_mm
// apart, their optical axes at least min_axis_angle_deg apart (two cameras
// looking the same way see one silhouette twice).
std::vector<std::string> extrinsics_problems(const CameraRig& rig, const RigRules& rules);

// Both of the above for a whole rig.
std::vector<std::string> rig_problems(const CameraRig& rig, const RigRules& rules);

}  // namespace spinewatch
