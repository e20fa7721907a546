#pragma once
// Whether one camera sees the whole subject: which image borders the
// person's blob touches. A setup aid (the daemon's live view): a blob cut
// by a border means the camera, or the worker's place, must move.
#include <cstdint>
#include <string>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {

struct ViewCoverage {
  std::int64_t pixels = 0;  // of the person's blob; 0: nobody in view
  bool left = false, right = false, top = false, bottom = false;  // borders the blob touches

  bool someone() const { return pixels > 0; }
  bool whole() const { return someone() && !left && !right && !top && !bottom; }
  // "whole", "nobody", or the borders that cut the subject ("cut at top, left").
  std::string describe() const;
};

// Reads the first and last rows and the first and last column of `person`.
ViewCoverage view_coverage(const BitMask& person);

}  // namespace spinewatch
