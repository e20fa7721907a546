#pragma once
// Frame pairs from the two V4L2 cameras: one capture thread per camera
// feeds the free-run pairer; pairs wait in a short queue for the pipeline.
#include <memory>

#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/pair_source.hpp"

namespace spinewatch {

struct CameraPairOptions {
  V4l2CameraOptions frontal, lateral;
  std::size_t ready_pairs = 2;  // paired, not yet taken by the pipeline (oldest dropped)
};

CameraPairOptions camera_pair_options(const Config& config);
// Starts both cameras; the error names the device and the problem.
// The devices are the system's, or fakes in tests.
Result<std::unique_ptr<PairSource>> open_camera_pair_source(const CameraPairOptions& options,
                                                            std::shared_ptr<V4l2Device> frontal = system_v4l2_device(),
                                                            std::shared_ptr<V4l2Device> lateral = system_v4l2_device());

}  // namespace spinewatch
