#include "spinewatch/sync/latency_histogram.hpp"

#include <algorithm>

namespace spinewatch::sync {

void LatencyHistogram::add(std::int64_t latency_ns) {
  const double us = static_cast<double>(std::max<std::int64_t>(latency_ns, 0)) / 1000.0;
  const auto bin = std::min<std::size_t>(static_cast<std::size_t>(us), kBins - 1);
  std::lock_guard lock(mutex_);
  ++bins_[bin];
  ++count_;
  sum_us_ += us;
  max_us_ = std::max(max_us_, us);
}

LatencySummary LatencyHistogram::summary() const {
  std::lock_guard lock(mutex_);
  LatencySummary s;
  s.count = count_;
  if (count_ == 0) return s;
  s.mean_us = sum_us_ / static_cast<double>(count_);
  s.max_us = max_us_;
  auto quantile = [&](double q) {
    const auto rank = static_cast<std::uint64_t>(q * static_cast<double>(count_ - 1));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
      seen += bins_[i];
      if (seen > rank) return static_cast<double>(i) + 0.5;  // bin centre
    }
    return max_us_;
  };
  s.p50_us = quantile(0.50);
  s.p99_us = quantile(0.99);
  return s;
}

}  // namespace spinewatch::sync
