// This build has no libcamera: the API exists so that callers need no
// #ifdef, and every call says why it cannot work.
#include "spinewatch/capture/libcamera_camera.hpp"

namespace spinewatch {
namespace {
Error not_built() { return Error{"libcamera: not available in this build (libcamera-dev was not found)"}; }
}  // namespace

struct LibcameraCamera::State {};

bool libcamera_built() { return false; }
Result<std::vector<LibcameraCameraInfo>> list_libcamera_cameras() { return not_built(); }
Result<std::unique_ptr<LibcameraCamera>> LibcameraCamera::open(LibcameraCameraOptions) { return not_built(); }
LibcameraCamera::LibcameraCamera(std::shared_ptr<State> state) : state_(std::move(state)) {}
LibcameraCamera::~LibcameraCamera() = default;
Status LibcameraCamera::start() { return not_built(); }
std::optional<Frame> LibcameraCamera::next(std::chrono::milliseconds) { return std::nullopt; }
void LibcameraCamera::stop() {}
CameraCounters LibcameraCamera::counters() const { return {}; }
FrameFormat LibcameraCamera::format() const { return {}; }
double LibcameraCamera::fps() const { return 0.0; }
const std::string& LibcameraCamera::name() const {
  static const std::string none;
  return none;
}

}  // namespace spinewatch
