#pragma once
// The readers behind load_camera_array (foreign_calibration.hpp), one per
// family of formats, and the checks they share.
#include <string>

#include "spinewatch/estimator/calibration/foreign_calibration.hpp"

namespace spinewatch::foreign_detail {

// caliscope's camera_array.toml or anipose's calibration.toml, told apart
// by their tables; an Error when `text` is TOML of neither kind.
Result<CameraArray> read_toml_array(const std::string& text, const std::string& file);
// OpenCV FileStorage JSON with the nodes frontal and lateral.
Result<CameraArray> read_opencv_json(const std::string& text, const std::string& file);

// fx, fy > 0, a rotation that is one (orthonormal, det +1), all finite.
Status check_camera(const CameraModel& model, const std::string& where);

}  // namespace spinewatch::foreign_detail
