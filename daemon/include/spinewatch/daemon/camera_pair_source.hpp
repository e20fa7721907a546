#pragma once
// Frame pairs from the two cameras (V4L2 or libcamera): one capture thread per camera
// feeds the pairer, and in master or slave mode the trigger's edges too
// (frames are then matched to edges); pairs wait in a short queue for the
// pipeline.
#include <functional>
#include <memory>

#include "spinewatch/capture/libcamera_camera.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/sync/frame_pairer.hpp"
#include "spinewatch/sync/trigger_source.hpp"

namespace spinewatch {

struct CameraPairOptions {
  V4l2CameraOptions frontal, lateral;
  std::size_t ready_pairs = 2;  // paired, not yet taken by the pipeline (oldest dropped)
  sync::TriggerSourceOptions trigger;  // free-run: frames paired with each other
  std::int64_t frame_latency_ns = 0;   // trigger edge → frame timestamp
};

// Makes the trigger that feeds edges to the callback; the default opens the
// GPIO line of options.trigger (tests pass one over a fake line).
using TriggerFactory =
    std::function<Result<std::unique_ptr<sync::TriggerSource>>(sync::TriggerSource::EdgeCallback on_edge)>;

// The one mapping of [cameras] and [trigger] to camera, trigger and
// pairing options (spinewatchd, and `spinewatch record` with its own
// device paths).
CameraPairOptions camera_pair_options(const Config& config);
sync::PairerOptions pairer_options(const CameraPairOptions& options);
// Starts both cameras; the error names the device and the problem.
// The devices are the system's, or fakes in tests.
Result<std::unique_ptr<PairSource>> open_camera_pair_source(const CameraPairOptions& options,
                                                            std::shared_ptr<V4l2Device> frontal = system_v4l2_device(),
                                                            std::shared_ptr<V4l2Device> lateral = system_v4l2_device(),
                                                            TriggerFactory make_trigger = {});

// The same over two libcamera cameras (cameras.source = "libcamera"):
// cameras.frontal and cameras.lateral are libcamera camera ids. Without
// libcamera in the build, an error saying so.
Result<std::unique_ptr<PairSource>> open_libcamera_pair_source(const Config& config);

}  // namespace spinewatch
