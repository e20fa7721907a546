#pragma once
// The daemon's processing chain: a source thread pulls frame pairs and
// numbers them, a bounded queue hands them to the estimator thread, which
// turns each into a Posture and hands it, with its pair, to the handler (the
// daemon's outputs, which never block). The estimator thread never waits on I/O.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>

#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "support/bounded_queue.hpp"

namespace spinewatch {

// The estimator stage (PostureEstimator::process in the daemon, fakes in tests).
using PostureFn = std::function<Posture(const FramePair&)>;
// Receives every posture, with the pair it came from, on the estimator
// thread; must not block.
using PostureHandler = std::function<void(const Posture&, const FramePair&)>;

struct PipelineOptions {
  std::size_t pair_queue = 4;  // pairs waiting for the estimator before the oldest is dropped
  // The source waits for the estimator instead (fast replay of a recording:
  // a file, unlike a camera, can wait).
  bool lossless = false;
};

struct PipelineStats {
  std::uint64_t pairs = 0;          // pairs taken from the source since start
  std::uint64_t pairs_dropped = 0;  // pairs dropped because the estimator fell behind
  std::uint64_t pairs_processed = 0;
  std::size_t pair_queue = 0;           // pairs waiting for the estimator now
  std::size_t pair_queue_capacity = 0;
  SourceStats source;
};

class Pipeline {
 public:
  Pipeline(std::unique_ptr<PairSource> source, PostureFn estimate, PostureHandler handler, PipelineOptions options = {});
  ~Pipeline();  // stops and joins
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  void start();
  // Stops the source, lets the estimator finish the pair in hand, joins both
  // threads. Idempotent.
  void stop();
  // True once the source thread has returned (source exhausted or stopped).
  bool source_finished() const { return source_finished_.load(); }

  PipelineStats stats() const;
  const PairSource& source() const { return *source_; }

 private:
  struct Queued {
    FramePair pair;
    std::int64_t received_ns;  // CLOCK_MONOTONIC when the source handed it over
  };
  void run_source();
  void run_estimator();

  std::unique_ptr<PairSource> source_;
  PostureFn estimate_;
  PostureHandler handler_;
  BoundedQueue<Queued> queue_;
  const bool lossless_;
  std::atomic<std::uint64_t> pairs_{0}, pairs_dropped_{0}, pairs_processed_{0};
  std::atomic<bool> source_finished_{false};
  std::jthread source_thread_, estimator_thread_;
  bool stopped_ = false;
};

}  // namespace spinewatch
