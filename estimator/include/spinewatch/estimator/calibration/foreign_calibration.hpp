#pragma once
// Calibrations written by other tools, read into the station's camera
// model (docs/import.md, "Calibrations accepted"):
//  - caliscope's camera_array.toml ([cameras.N]: size, matrix, distortions,
//    rotation 3×3 and translation in metres, world → camera as OpenCV's
//    extrinsics; rotation_count only turns caliscope's display, the
//    calibration stays in the video's own pixel frame);
//  - anipose / aniposelib calibration.toml ([cam_N]: name, size, matrix,
//    distortions, rotation as a Rodrigues vector, translation, world →
//    camera; units those of the board, taken as millimetres unless the
//    cameras would then stand within 20 units of each other — then metres,
//    and the array says so in its notes);
//  - the station's own calibration.yaml (OpenCV FileStorage YAML, as
//    load_calibration reads it) and the same nodes as OpenCV JSON: two
//    cameras, `frontal` and `lateral`.
// Every camera keeps the file's world frame; translations in millimetres.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct NamedCamera {
  std::string id;    // caliscope: the port ("0"); anipose: the table ("cam_0"); station: "frontal"
  std::string name;  // caliscope: "cam_0" (its video's name); anipose: `name`; station: as id
  CameraModel model; // x_cam = R · X_file + t, t in mm; image_width/height set
  double rms_px = -1;        // the tool's reprojection error; negative when the file has none
  bool ignored = false;      // caliscope's `ignore = true`: left out of its calibration
  bool has_extrinsics = true;
  int rotation_count = 0;    // caliscope's display rotation in quarter turns (informative only)
};

struct CameraArray {
  std::string format;  // "caliscope", "anipose", "opencv-yaml", "opencv-json"
  std::string source;  // the file, for messages
  std::vector<NamedCamera> cameras;
  std::vector<std::string> notes;  // choices made while reading (units), to print
};

// Reads any of the formats above, told apart by their content (not the
// file's name). Errors name the file, the line where known, the field and
// what is wrong.
Result<CameraArray> load_camera_array(const std::filesystem::path& path);

// One camera by its id or name (case-sensitive; "cam_0", "0" and
// "frontal" all work where the file has them).
Result<const NamedCamera*> find_camera(const CameraArray& array, std::string_view id_or_name);

// The station's two cameras from an array: by id or name; with both empty,
// the station file's frontal/lateral, or else the array's first two usable
// cameras. A camera that is missing, ignored or without extrinsics is an
// error listing the cameras the file holds.
Result<CameraRig> select_pair(const CameraArray& array, std::string_view frontal, std::string_view lateral);

// "0 (cam_0), 1 (cam_1), …": for messages.
std::string list_cameras(const CameraArray& array);

}  // namespace spinewatch
