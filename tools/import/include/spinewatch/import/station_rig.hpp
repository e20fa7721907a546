#pragma once
// The station's two cameras from another tool's calibration file, in the
// station's world frame (world_frame.hpp): what `spinewatch import` crops
// and `spinewatch calibrate --from` writes as it is.
#include <filesystem>
#include <string>
#include <vector>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/import/world_frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::import {

struct RigChoice {
  std::filesystem::path calibration;
  std::string frontal, lateral;  // ids or names; both empty: the file's first two usable cameras
  std::string up;                // "X,Y,Z" in the file's frame; empty: estimated
  double camera_height_mm = 1100;
};

struct StationRig {
  CameraRig rig;                // station frame, mm; intrinsics and image size as in the file
  std::string format;           // the file's format ("caliscope", …)
  std::string ids[2];           // the cameras chosen
  WorldFrame frame;             // the station's frame in the file's
  std::vector<std::string> report;  // how the file was read, the cameras and the world frame chosen, a line each
};

Result<StationRig> station_rig_from(const RigChoice& choice);

}  // namespace spinewatch::import
