#include "cvsm/silhouette_edges.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace spinewatch::cvsm_detail {

void SilhouetteEdges::assign(const BitMask& silhouette) {
  const int width = silhouette.width(), height = silhouette.height(), words = silhouette.words_per_row();
  if (rising_.width() != width || rising_.height() != height) {
    rising_ = BitMask(width, height);
    falling_ = BitMask(width, height);
  }
  // The last pixel of a row: bit (width − 1) of the last word.
  const std::uint64_t last_bit = std::uint64_t{1} << ((width - 1) & 63);
  for (int y = 0; y < height; ++y) {
    const std::uint64_t* s = silhouette.row(y);
    std::uint64_t* up = rising_.row(y);
    std::uint64_t* down = falling_.row(y);
    for (int w = 0; w < words; ++w) {
      // The neighbours of each bit: the pixel before (carried in from the
      // word before; the first pixel has none) and the pixel after.
      const std::uint64_t before = (s[w] << 1) | (w > 0 ? s[w - 1] >> 63 : 1u);
      const std::uint64_t after = (s[w] >> 1) | (w + 1 < words ? s[w + 1] << 63 : 0u);
      up[w] = s[w] & ~before;
      down[w] = s[w] & ~after;
    }
    // The image's last pixel has no pixel after it: no edge there.
    down[words - 1] &= ~last_bit;
  }
}

namespace {

// The highest set bit at or below pixel q of a packed row (−1: none), and
// the lowest at or above it (`words` · 64: none).
int set_at_or_below(const std::uint64_t* row, int q) {
  int w = q >> 6;
  std::uint64_t bits = row[w] & (~std::uint64_t{0} >> (63 - (q & 63)));
  while (bits == 0) {
    if (--w < 0) return -1;
    bits = row[w];
  }
  return (w << 6) + 63 - std::countl_zero(bits);
}
int set_at_or_above(const std::uint64_t* row, int words, int q) {
  int w = q >> 6;
  std::uint64_t bits = row[w] & (~std::uint64_t{0} << (q & 63));
  while (bits == 0) {
    if (++w == words) return words << 6;
    bits = row[w];
  }
  return (w << 6) + std::countr_zero(bits);
}

}  // namespace

float SilhouetteEdges::nearest(int y, float x, bool right, int window) const {
  const BitMask& edges = right ? falling_ : rising_;
  // Pixel p's edge lies at p + half: the pixel nearest x's is p ≈ x − half.
  const float half = right ? 0.5f : -0.5f;
  const float c = x - half;
  const int below = std::clamp(static_cast<int>(std::floor(c)), -1, edges.width() - 1);
  const std::uint64_t* row = edges.row(y);
  const int words = edges.words_per_row();
  const int lo = below >= 0 ? set_at_or_below(row, below) : -1;
  const int hi = below + 1 < edges.width() ? set_at_or_above(row, words, below + 1) : words << 6;
  const float d_lo = lo >= 0 ? c - static_cast<float>(lo) : std::numeric_limits<float>::infinity();
  const float d_hi = hi < edges.width() ? static_cast<float>(hi) - c : std::numeric_limits<float>::infinity();
  const float d = std::min(d_lo, d_hi);
  if (d > static_cast<float>(window)) return std::numeric_limits<float>::quiet_NaN();
  // A tie goes to the edge on the right, as a scan from the left finds it last.
  return (d_hi <= d_lo ? static_cast<float>(hi) : static_cast<float>(lo)) + half;
}

}  // namespace spinewatch::cvsm_detail
