#include "cvsm/unseen_end.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace spinewatch::cvsm_detail {

double share_ending_on_unseen(const BitMask& silhouette, const BitMask& unseen) {
  const int height = silhouette.height(), words = silhouette.words_per_row();
  if (unseen.width() != silhouette.width() || unseen.height() != height) return 0;
  // Bottom up: a column's bit first set at row y is its lowest pixel there.
  std::vector<std::uint64_t> seen(static_cast<std::size_t>(words), 0);
  std::int64_t on_unseen = 0;
  for (int y = height - 1; y >= 0; --y) {
    const std::uint64_t* row = silhouette.row(y);
    for (int w = 0; w < words; ++w) {
      const std::uint64_t fresh = row[w] & ~seen[static_cast<std::size_t>(w)];
      if (!fresh) continue;
      seen[static_cast<std::size_t>(w)] |= fresh;
      std::uint64_t below = 0;
      for (int b = y + 1; b <= std::min(height - 1, y + kUnseenEndGapPx); ++b) below |= unseen.row(b)[w];
      on_unseen += std::popcount(fresh & below);
    }
  }
  std::int64_t columns = 0;
  for (const std::uint64_t s : seen) columns += std::popcount(s);
  return columns ? static_cast<double>(on_unseen) / static_cast<double>(columns) : 0;
}

}  // namespace spinewatch::cvsm_detail
