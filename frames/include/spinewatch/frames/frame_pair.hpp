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
  // No frames: a marker that a camera went away here (the daemon's camera
  // source makes it when a camera's `losses` counter grows). The daemon
  // publishes it as a `lost` line flagged `camera_lost`, so the gap shows
  // in the stream where it began, not only in counters.
  bool camera_lost = false;
};

}  // namespace spinewatch
