#include "spinewatch/sync/pairing_stats.hpp"

#include <cstdlib>

#include <fmt/format.h>

namespace spinewatch::sync {

void SkewStats::add(std::int64_t skew_ns) {
  ++count;
  mean_ns += (static_cast<double>(skew_ns) - mean_ns) / static_cast<double>(count);
  const std::int64_t a = skew_ns < 0 ? -skew_ns : skew_ns;
  if (a > max_abs_ns) max_abs_ns = a;
}

std::string PairingStats::summary() const {
  std::string out = fmt::format("pairs {} (skew mean {:.3f} ms, max {:.3f} ms)", pairs, pair_skew.mean_ns / 1e6,
                                static_cast<double>(pair_skew.max_abs_ns) / 1e6);
  const char* names[2] = {"frontal", "lateral"};
  for (int s = 0; s < 2; ++s) {
    const auto& d = drops[s];
    out += fmt::format("; {} in {} unmatched {} duplicate {} late {} overflow {} flushed {} seq-gaps {}", names[s],
                       frames_in[s], d.unmatched, d.duplicate, d.late, d.overflow, d.flushed, d.sequence_gaps);
  }
  if (triggers_in > 0) {
    out += fmt::format("; triggers {} unpaired {}", triggers_in, triggers_unpaired);
    // What trigger.frame_latency_us should absorb (docs/hardware.md).
    for (int s = 0; s < 2; ++s)
      out += fmt::format("; {} frame − edge mean {:.3f} ms", names[s], trigger_skew[s].mean_ns / 1e6);
  }
  return out;
}

}  // namespace spinewatch::sync
