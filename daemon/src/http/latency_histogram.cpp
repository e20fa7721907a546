#include "http/latency_histogram.hpp"

#include <algorithm>

namespace spinewatch {

void LatencyHistogram::observe_us(std::int64_t latency_us) {
  const std::int64_t us = std::max<std::int64_t>(0, latency_us);
  const double s = static_cast<double>(us) * 1e-6;
  const auto bucket = static_cast<std::size_t>(std::lower_bound(kBounds.begin(), kBounds.end(), s) - kBounds.begin());
  buckets_[bucket].fetch_add(1, std::memory_order_relaxed);
  count_.fetch_add(1, std::memory_order_relaxed);
  sum_us_.fetch_add(static_cast<std::uint64_t>(us), std::memory_order_relaxed);
}

LatencyHistogram::Counts LatencyHistogram::counts() const {
  Counts c;
  for (std::size_t i = 0; i < buckets_.size(); ++i) c.buckets[i] = buckets_[i].load(std::memory_order_relaxed);
  c.count = count_.load(std::memory_order_relaxed);
  c.sum_s = static_cast<double>(sum_us_.load(std::memory_order_relaxed)) * 1e-6;
  return c;
}

}  // namespace spinewatch
