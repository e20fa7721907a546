#pragma once
#include "spinewatch/daemon/config.hpp"
#include "spinewatch/estimator/pipeline.hpp"

namespace spinewatch {

// The estimator's options from the station configuration, the model
// files aside (cvsm.model, spine.model: the generic models).
EstimatorOptions estimator_options(const Config& config);
// The same with the model files read and parsed; an error names the key,
// the file and what is wrong.
Result<EstimatorOptions> load_estimator_options(const Config& config);

}  // namespace spinewatch
