#include "silhouette/scene_edges.hpp"

#include <bit>
#include <cstdint>

namespace spinewatch::silhouette_detail {
namespace {

// Squared 3×3 Sobel magnitude of the background at (x, y), inside the image.
int sobel_squared(const BackgroundModel& bg, int x, int y) {
  const std::uint8_t* a = bg.row(y - 1);
  const std::uint8_t* b = bg.row(y);
  const std::uint8_t* c = bg.row(y + 1);
  const int gx = (a[x + 1] + 2 * b[x + 1] + c[x + 1]) - (a[x - 1] + 2 * b[x - 1] + c[x - 1]);
  const int gy = (c[x - 1] + 2 * c[x] + c[x + 1]) - (a[x - 1] + 2 * a[x] + a[x + 1]);
  return gx * gx + gy * gy;
}

}  // namespace

void mark_scene_edges(const BitMask& person, const BackgroundModel& background, int min_gradient, BitMask& out) {
  const int w = person.width(), h = person.height();
  out = BitMask(w, h);
  if (w < 3 || h < 3 || background.width() != w || background.height() != h) return;
  const int words = person.words_per_row();
  const int min_squared = min_gradient * min_gradient;
  // Only rows 1 … h − 2 can be marked; their neighbours are always rows.
  for (int y = 1; y < h - 1; ++y) {
    const std::uint64_t* up = person.row(y - 1);
    const std::uint64_t* row = person.row(y);
    const std::uint64_t* down = person.row(y + 1);
    std::uint64_t* marked = out.row(y);
    for (int k = 0; k < words; ++k) {
      const std::uint64_t m = row[k];
      if (!m) continue;
      // Each pixel's left and right neighbours, across the word's ends.
      const std::uint64_t left = (m << 1) | (k > 0 ? row[k - 1] >> 63 : 0);
      const std::uint64_t right = (m >> 1) | (k + 1 < words ? row[k + 1] << 63 : 0);
      std::uint64_t outline = m & ~(left & right & up[k] & down[k]);
      while (outline) {
        const int bit = std::countr_zero(outline);
        outline &= outline - 1;
        const int x = k * 64 + bit;
        if (x < 1 || x >= w - 1) continue;
        if (sobel_squared(background, x, y) >= min_squared) marked[k] |= std::uint64_t{1} << bit;
      }
    }
  }
}

}  // namespace spinewatch::silhouette_detail
