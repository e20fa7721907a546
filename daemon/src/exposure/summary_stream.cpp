#include "exposure/summary_stream.hpp"

#include <time.h>

namespace spinewatch {
namespace {

ExposureOptions aligned(ExposureOptions options, const SummaryLabels& labels) {
  if (labels.utc_offset_ns) options.align_ns = *labels.utc_offset_ns;
  return options;
}

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  ::clock_gettime(clock, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

SummaryStream::SummaryStream(ExposureOptions options, SummaryLabels labels)
    : accumulator_(aligned(std::move(options), labels)), labels_(std::move(labels)) {}

std::vector<SummaryLine> SummaryStream::encode(const std::vector<ExposureSummary>& closed) const {
  std::vector<SummaryLine> lines;
  lines.reserve(closed.size());
  for (const ExposureSummary& s : closed) lines.push_back({s, encode_summary(s, labels_)});
  return lines;
}

std::int64_t realtime_minus_monotonic_ns() {
  // Read monotonic on both sides of the realtime read; the midpoint halves the error.
  const std::int64_t m0 = clock_ns(CLOCK_MONOTONIC);
  const std::int64_t r = clock_ns(CLOCK_REALTIME);
  const std::int64_t m1 = clock_ns(CLOCK_MONOTONIC);
  return r - (m0 + (m1 - m0) / 2);
}

}  // namespace spinewatch
