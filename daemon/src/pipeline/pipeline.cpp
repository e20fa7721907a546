#include "pipeline/pipeline.hpp"

#include <time.h>

#include <spdlog/spdlog.h>

#include "spinewatch/estimator/fit_flags.hpp"
#include "spinewatch/frames/clock.hpp"

namespace spinewatch {

PairSource::~PairSource() = default;

Pipeline::Pipeline(std::unique_ptr<PairSource> source, PostureFn estimate, PostureHandler handler, PipelineOptions options)
    : source_(std::move(source)), estimate_(std::move(estimate)), handler_(std::move(handler)), queue_(options.pair_queue), lossless_(options.lossless) {}

Pipeline::~Pipeline() { stop(); }

void Pipeline::start() {
  estimator_thread_ = std::jthread([this] { run_estimator(); });
  source_thread_ = std::jthread([this] { run_source(); });
}

void Pipeline::stop() {
  if (stopped_) return;
  stopped_ = true;
  source_->stop();
  queue_.close();  // also frees a source thread waiting for room
  if (source_thread_.joinable()) source_thread_.join();
  if (estimator_thread_.joinable()) estimator_thread_.join();
}

void Pipeline::run_source() {
  // seq counts pairs since start, whatever the source numbers them (a looping
  // recording restarts its own numbering), so a gap means a dropped pair.
  std::uint64_t seq = 0;
  while (auto pair = source_->next()) {
    pair->sequence = seq++;
    if (!pair->camera_lost) pairs_.fetch_add(1, std::memory_order_relaxed);
    Queued item{std::move(*pair), monotonic_now_ns()};
    if (lossless_) {
      if (!queue_.push_waiting(std::move(item))) break;
    } else if (queue_.push(std::move(item))) {
      pairs_dropped_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  source_finished_ = true;
  queue_.close();  // the estimator drains what is queued, then ends
}

void Pipeline::run_estimator() {
  while (auto item = queue_.pop()) {
    Posture posture;
    try {
      if (item->pair.camera_lost) {
        // Not a pair: a camera went away here. One lost line marks the gap.
        posture.state = TrackingState::Lost;
        posture.fit.flag = std::string(kCameraLostFlag);
      } else {
        posture = estimate_(item->pair);
      }
    } catch (const std::exception& e) {
      // A bug in one stage must not take the station down; report the pair lost.
      spdlog::error("estimator failed on pair {}: {}", item->pair.sequence, e.what());
      posture = Posture{};
      posture.state = TrackingState::Lost;
      posture.fit.flag = std::string(kEstimatorErrorFlag);
    }
    posture.seq = item->pair.sequence;
    posture.t_ns = item->pair.timestamp_ns;
    posture.latency_us = std::max<std::int64_t>(0, (monotonic_now_ns() - item->received_ns) / 1000);
    pairs_processed_.fetch_add(1, std::memory_order_relaxed);
    handler_(posture, item->pair);
  }
}

PipelineStats Pipeline::stats() const {
  PipelineStats s;
  s.pairs = pairs_.load(std::memory_order_relaxed);
  s.pairs_dropped = pairs_dropped_.load(std::memory_order_relaxed);
  s.pairs_processed = pairs_processed_.load(std::memory_order_relaxed);
  s.pair_queue = queue_.size();
  s.pair_queue_capacity = queue_.capacity();
  s.source = source_->stats();
  return s;
}

}  // namespace spinewatch
