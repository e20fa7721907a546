#pragma once
#include <cstdint>

#include "spinewatch/frames/frame.hpp"

namespace spinewatch {

// Two frames exposed at the same instant, one per view. `sequence` counts
// pairs (in a recording: the pair's index; in the daemon: pairs since
// start); `timestamp_ns` is the pair's capture time.
struct FramePair {
  std::uint64_t sequence = 0;
  std::int64_t timestamp_ns = 0;
  Frame frontal;
  Frame lateral;
};

}  // namespace spinewatch
