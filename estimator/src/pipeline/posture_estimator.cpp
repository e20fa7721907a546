// INTEGRATION PENDING: the stages (silhouette, cvsm, spine, load) are being
// built; until they are wired here every pair is reported lost.
#include "spinewatch/estimator/pipeline.hpp"

namespace spinewatch {

struct PostureEstimator::Impl {
  CameraRig rig;
  EstimatorOptions options;
};

PostureEstimator::PostureEstimator(const CameraRig& rig, const EstimatorOptions& options)
    : impl_(std::make_unique<Impl>(Impl{rig, options})) {}

PostureEstimator::~PostureEstimator() = default;

Posture PostureEstimator::process(const FramePair& pair) {
  Posture p;
  p.seq = pair.sequence;
  p.t_ns = pair.timestamp_ns;
  p.state = TrackingState::Lost;
  p.fit.flag = "pending_integration";
  return p;
}

}  // namespace spinewatch
