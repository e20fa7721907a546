#include "spinewatch/estimator/silhouette/bit_mask.hpp"

#include <algorithm>

namespace spinewatch {

void BitMask::set_span(int y, int x0, int x1) {
  x0 = std::max(x0, 0);
  x1 = std::min(x1, width_ - 1);
  if (y < 0 || y >= height_ || x0 > x1) return;
  set_bits(row(y), x0, x1);
}

std::int64_t BitMask::count_row(int y) const {
  std::int64_t n = 0;
  const std::uint64_t* r = row(y);
  for (int w = 0; w < words_per_row_; ++w) n += std::popcount(r[w]);
  return n;
}

std::int64_t BitMask::count() const {
  std::int64_t n = 0;
  for (std::uint64_t w : words_) n += std::popcount(w);
  return n;
}

}  // namespace spinewatch
