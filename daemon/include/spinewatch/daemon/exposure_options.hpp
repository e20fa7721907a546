#pragma once
// The exposure summaries' settings from the station configuration
// ([exposure]; the limits are config/segments.toml's, as the per-frame
// ergonomic flags have them).
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/load/alerts.hpp"
#include "spinewatch/estimator/load/exposure_accumulator.hpp"

namespace spinewatch {

ExposureOptions exposure_options(const Config& config);
// [alerts]: the rules (none when alerts.enabled is false; the built-in
// ones when alerts.rules is ""); an error names the file, line and key.
Result<std::vector<AlertRule>> load_alert_rules(const Config& config);

}  // namespace spinewatch
