#pragma once
// spinewatch import (interfaces.md §4; docs/import.md): two video files and
// another tool's calibration into a recording directory (§2) — frames
// cropped and scaled to 320×240 YUYV, calibration.yaml for exactly that
// crop and scale in the station's world frame (§1), optional backgrounds.
#include <filesystem>
#include <optional>
#include <string>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::import {

struct ImportOptions {
  std::filesystem::path frontal_video, lateral_video, calibration, out;
  std::string frontal_camera, lateral_camera;  // ids or names in the calibration; empty: its first two
  std::filesystem::path background_frontal, background_lateral;  // images of the empty scene, the videos' size
  bool median_background = false;  // the clip's per-pixel median as the background (a scene with motion)
  int offset = 0;                  // lateral frame i + offset pairs with frontal frame i
  std::optional<int> frames;       // import this many pairs (else all; the clips must then match)
  std::string crop_frontal, crop_lateral;  // "X,Y,W,H"; empty: from the clip's motion
  std::string up;                          // "X,Y,Z" in the calibration's frame; empty: estimated
  double camera_height_mm = 1100;          // the cameras' mean height above the floor
};

// What was written, for the caller's summary.
struct ImportSummary {
  int pairs = 0;
  double seconds = 0;
};

Result<ImportSummary> import_recording(const ImportOptions& options);

}  // namespace spinewatch::import
