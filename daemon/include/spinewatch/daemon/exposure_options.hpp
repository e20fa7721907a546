#pragma once
// The exposure summaries' settings from the station configuration
// ([exposure]; the limits are config/segments.toml's, as the per-frame
// ergonomic flags have them).
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/daemon/store.hpp"
#include "spinewatch/estimator/load/exposure_accumulator.hpp"

namespace spinewatch {

ExposureOptions exposure_options(const Config& config);
// [storage]: the database's settings.
StoreOptions store_options(const Config& config);

}  // namespace spinewatch
