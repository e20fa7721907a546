#pragma once
// Wake-up latency of the trigger thread (actual − deadline), in 1 µs bins
// up to 10 ms; read from any thread.
#include <array>
#include <cstdint>
#include <mutex>

namespace spinewatch::sync {

struct LatencySummary {
  std::uint64_t count = 0;
  double mean_us = 0.0;
  double p50_us = 0.0;
  double p99_us = 0.0;
  double max_us = 0.0;
};

class LatencyHistogram {
 public:
  void add(std::int64_t latency_ns);
  LatencySummary summary() const;

 private:
  static constexpr std::size_t kBins = 10'000;  // 1 µs each; the last holds everything beyond
  mutable std::mutex mutex_;
  std::array<std::uint32_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  double sum_us_ = 0.0;
  double max_us_ = 0.0;
};

}  // namespace spinewatch::sync
