#include "app/posture_counters.hpp"

namespace spinewatch {

void PostureCounters::observe(const Posture& posture) {
  last_state_.store(static_cast<int>(posture.state), std::memory_order_relaxed);
  latency_.observe_us(posture.latency_us);
  by_state_[static_cast<std::size_t>(posture.state)].fetch_add(1, std::memory_order_relaxed);
  if (previous_state_ == TrackingState::Tracking && posture.state == TrackingState::Lost)
    tracking_lost_.fetch_add(1, std::memory_order_relaxed);
  previous_state_ = posture.state;
  background_updates_.store(posture.background.updates, std::memory_order_relaxed);
  background_relearns_.store(posture.background.relearns, std::memory_order_relaxed);
  background_bootstraps_.store(posture.background.bootstraps, std::memory_order_relaxed);
}

void PostureCounters::add_metrics(DaemonMetrics& m) const {
  for (std::size_t i = 0; i < by_state_.size(); ++i) m.postures.by_state[i] = by_state_[i].load(std::memory_order_relaxed);
  m.postures.tracking_lost = tracking_lost_.load(std::memory_order_relaxed);
  m.background = {background_updates_.load(std::memory_order_relaxed),
                  background_relearns_.load(std::memory_order_relaxed),
                  background_bootstraps_.load(std::memory_order_relaxed)};
  m.latency = latency_.counts();
}

}  // namespace spinewatch
