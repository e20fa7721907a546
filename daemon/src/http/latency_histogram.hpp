#pragma once
// The per-pair latency (source hand-over → posture ready) as a Prometheus
// histogram. observe() runs on the estimator thread for every pair: one
// bucket and two totals, relaxed atomics, no lock. counts() may be read
// from any thread; a read racing an observe() may see the bucket before
// the totals (Prometheus scrapes tolerate that).
#include <array>
#include <atomic>
#include <cstdint>

namespace spinewatch {

class LatencyHistogram {
 public:
  // Upper bounds in seconds; the 250 µs per-pair budget and the camera
  // period (33 ms) each fall on a bound.
  static constexpr std::array<double, 12> kBounds = {0.00025, 0.0005, 0.001, 0.002, 0.005, 0.01,
                                                     0.0333, 0.05,    0.1,   0.25,  0.5,   1.0};
  struct Counts {
    std::array<std::uint64_t, kBounds.size() + 1> buckets{};  // per bucket (not cumulative), the last +Inf
    std::uint64_t count = 0;
    double sum_s = 0;
  };

  void observe_us(std::int64_t latency_us);
  Counts counts() const;

 private:
  std::array<std::atomic<std::uint64_t>, kBounds.size() + 1> buckets_{};
  std::atomic<std::uint64_t> count_{0}, sum_us_{0};
};

}  // namespace spinewatch
