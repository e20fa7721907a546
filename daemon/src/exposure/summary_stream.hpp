#pragma once
// The daemon's exposure summaries (docs/exposure.md): postures in, on the
// estimator thread (a few additions per pair, nothing that blocks);
// "summary" lines out, to publish after the posture that closed them.
#include <cstdint>
#include <string>
#include <vector>

#include "spinewatch/estimator/load/exposure_accumulator.hpp"
#include "spinewatch/estimator/load/exposure_json.hpp"

namespace spinewatch {

struct SummaryLine {
  ExposureSummary summary;
  std::string line;  // the stream line, without its newline
};

class SummaryStream {
 public:
  // labels.utc_offset_ns also aligns the intervals to the wall clock.
  SummaryStream(ExposureOptions options, SummaryLabels labels);

  std::vector<SummaryLine> add(const Posture& posture) { return encode(accumulator_.add(posture)); }
  // The last partial interval and the shift, at stop.
  std::vector<SummaryLine> finish() { return encode(accumulator_.finish()); }
  // A new worker in view: the previous one's last interval and shift,
  // then summaries carry `id` (none: no "worker" field).
  std::vector<SummaryLine> set_worker(std::optional<std::string> id) {
    auto lines = finish();
    labels_.worker = std::move(id);
    return lines;
  }

 private:
  std::vector<SummaryLine> encode(const std::vector<ExposureSummary>& closed) const;

  ExposureAccumulator accumulator_;
  SummaryLabels labels_;
};

// CLOCK_REALTIME − CLOCK_MONOTONIC now: the wall-clock time of a
// monotonic timestamp t is t + this.
std::int64_t realtime_minus_monotonic_ns();

}  // namespace spinewatch
