#pragma once
// A PairSource for tests: synthetic 320×240 GREY pairs, as fast as asked
// or until a count, restarting its own numbering every `lap` pairs the way a
// looping recording might.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "spinewatch/daemon/pair_source.hpp"
#include "spinewatch/estimator/posture.hpp"

namespace spinewatch::test {

class FakePairSource final : public PairSource {
 public:
  struct Options {
    std::uint64_t count = 100;  // pairs before the end; 0: block after none (until stop)
    std::uint64_t lap = 0;      // numbering restarts every `lap` pairs (0: never)
    std::uint32_t width = 320, height = 240;
    std::uint64_t camera_lost_at = 0;  // a camera_lost marker before this pair (0: none)
  };
  explicit FakePairSource(Options options) : options_(options) {}

  // The next pair; after `count` pairs, like a camera with nothing more to
  // say, it waits for stop().
  std::optional<FramePair> next() override;
  void stop() override;
  SourceStats stats() const override;
  std::string describe() const override { return "fake"; }

 private:
  Options options_;
  std::uint64_t produced_ = 0;
  bool marked_ = false;
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<bool> stopped_{false};
  std::mutex mutex_;
  std::condition_variable stop_cv_;
};

// The stand-in estimator: reports every pair lost.
Posture lost_posture(const FramePair& pair);

}  // namespace spinewatch::test
