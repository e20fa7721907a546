#pragma once
// What the daemon reads and checks before it starts anything: the rig's
// calibration, the empty scene, the listeners' options, the alert line.
// Each returns an error value naming the key or file at fault.
#include <memory>
#include <optional>
#include <string>

#include "exposure/alert_output.hpp"
#include "http/http_server.hpp"
#include "publish/publisher.hpp"
#include "source/source_plan.hpp"
#include "spinewatch/capture/background_images.hpp"
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch {

// `used`: the calibration file read, "" for the default rig.
Result<CameraRig> load_rig(const Config& config, const SourcePlan& plan, std::string& used);
Result<std::optional<BackgroundImages>> load_background(const Config& config, const SourcePlan& plan);
Result<PublisherOptions> publisher_options(const Config& config, const DaemonOverrides& overrides);
Result<std::optional<HttpOptions>> http_options(const Config& config, const DaemonOverrides& overrides);
Result<std::unique_ptr<AlertOutput>> open_alert_output(const Config::Alerts& alerts);

}  // namespace spinewatch
