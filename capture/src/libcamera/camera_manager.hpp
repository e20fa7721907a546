#pragma once
// libcamera allows one CameraManager per process: one shared instance,
// started on first use, stopped when the last holder lets go.
#include <memory>

#include <libcamera/camera_manager.h>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::lc {

Result<std::shared_ptr<libcamera::CameraManager>> shared_camera_manager();

}  // namespace spinewatch::lc
