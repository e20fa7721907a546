#include "spinewatch/estimator/silhouette/still_scenery.hpp"

#include <algorithm>
#include <bit>

namespace spinewatch {

bool StillScenery::still(const BitMask& other) {
  const std::int64_t px = other.count();
  if (px == 0) {
    reset();
    return false;
  }
  std::int64_t kept = 0;
  if (snapshot_.width() == other.width() && snapshot_.height() == other.height())
    for (int y = 0; y < other.height(); ++y) {
      const std::uint64_t* a = other.row(y);
      const std::uint64_t* b = snapshot_.row(y);
      for (int w = 0; w < other.words_per_row(); ++w) kept += std::popcount(a[w] & b[w]);
    }
  if (static_cast<double>(kept) >= kStillOverlap * static_cast<double>(std::max(px, snapshot_px_))) {
    ++frames_;
  } else {
    snapshot_ = other;
    snapshot_px_ = px;
    frames_ = 0;
  }
  return frames_ >= kStillFrames;
}

void StillScenery::reset() {
  snapshot_ = BitMask();
  snapshot_px_ = 0;
  frames_ = 0;
}

}  // namespace spinewatch
