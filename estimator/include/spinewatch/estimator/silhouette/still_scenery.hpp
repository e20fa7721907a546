#pragma once
// Foreground that is not the person and does not move (docs/cvsm.md,
// "Silhouettes", "Still scenery"): a chair moved, a bag set down, a door
// left open since the stored background was taken. Such a blob beside the
// subject made every pair `two_blobs` — the whole of a short clip lost —
// until the background's slow adaptation for foreground that is not the
// person (twenty times the person's time constant) took it in. A blob that
// keeps its place is no rival for the person's: the fit reads the person's
// blob alone, so a second blob is said only while it moves.
#include <cstdint>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {

class StillScenery {
 public:
  // The share of a still blob's pixels that must stay where they were
  // (against the snapshot taken when it appeared, and the snapshot's
  // against it): a standing person shifts by a few pixels and keeps about
  // nine tenths; one walking at 1 m/s moves 2–3 pixels a frame at 320
  // pixels and loses that within a few frames.
  static constexpr double kStillOverlap = 0.9;
  // Frames the foreground outside the person must keep to the snapshot
  // before it counts as scenery.
  static constexpr int kStillFrames = 10;

  // `other`: this frame's foreground outside the person's blob. True when
  // it has stayed within kStillOverlap of the snapshot for kStillFrames
  // frames or more; a frame that leaves it takes a new snapshot.
  bool still(const BitMask& other);
  void reset();

 private:
  BitMask snapshot_;
  std::int64_t snapshot_px_ = 0;
  int frames_ = 0;  // frames in a row that kept to the snapshot
};

}  // namespace spinewatch
