#pragma once
// What a caller (a test) puts in place of the station's own parts, for
// Daemon::create (spinewatch/daemon/daemon.hpp). Empty: all the station's
// own, as the configuration says.
#include <memory>
#include <vector>

#include "outputs/posture_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "spinewatch/daemon/daemon.hpp"
#include "spinewatch/daemon/pair_source.hpp"

namespace spinewatch {

struct DaemonParts {
  // Instead of the cameras or recording [cameras] names; it is read
  // lossless, as a fast replay: it waits for the estimator, no pair dropped.
  std::unique_ptr<PairSource> source;
  PostureFn estimate;                  // instead of the posture estimator
  // Outputs after the station's own (publisher, storage, MQTT, alert line,
  // live view); they stop last, in this order.
  std::vector<std::unique_ptr<PostureSink>> sinks;
};

}  // namespace spinewatch
