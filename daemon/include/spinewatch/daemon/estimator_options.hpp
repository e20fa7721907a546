#pragma once
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/pipeline.hpp"

namespace spinewatch {

// The estimator's options from the station configuration.
EstimatorOptions estimator_options(const Config& config);

}  // namespace spinewatch
