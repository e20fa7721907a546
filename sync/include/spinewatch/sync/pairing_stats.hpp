#pragma once
// What the pairer counts: pairs made, frames dropped by cause, and the
// timing skew of what it paired.
#include <cstdint>
#include <string>

namespace spinewatch::sync {

// Running statistics of a signed time difference (ns).
struct SkewStats {
  std::uint64_t count = 0;
  double mean_ns = 0.0;
  std::int64_t max_abs_ns = 0;

  void add(std::int64_t skew_ns);
};

// Frames of one stream that did not end up in a pair, by cause.
struct StreamDrops {
  std::uint64_t unmatched = 0;      // no partner (or trigger) within tolerance
  std::uint64_t duplicate = 0;      // a sequence number seen before
  std::uint64_t late = 0;           // arrived after its time had been decided
  std::uint64_t overflow = 0;       // oldest dropped to bound memory (stalled partner/trigger)
  std::uint64_t flushed = 0;        // still waiting at flush()
  std::uint64_t sequence_gaps = 0;  // never delivered: gaps in the driver's sequence numbers

  std::uint64_t total_discarded() const { return unmatched + duplicate + late + overflow + flushed; }
};

struct PairingStats {
  std::uint64_t pairs = 0;
  std::uint64_t frames_in[2] = {0, 0};
  StreamDrops drops[2];
  // Triggered mode: edges that got no complete pair (a frame missing, or
  // dropped for memory), and edges dropped for memory while still empty.
  std::uint64_t triggers_in = 0;
  std::uint64_t triggers_unpaired = 0;
  std::uint64_t triggers_overflow = 0;
  SkewStats pair_skew;        // lateral − frontal frame time of each pair
  SkewStats trigger_skew[2];  // frame time (minus latency) − trigger time, per stream

  std::string summary() const;  // one line for a log
};

}  // namespace spinewatch::sync
