#include "cvsm/lower_residual.hpp"

#include <algorithm>
#include <bit>

namespace spinewatch::cvsm_detail {

std::int64_t xor_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden, int first_row) {
  std::int64_t n = 0;
  const int words = model.words_per_row();
  for (int y = std::max(0, first_row); y < model.height(); ++y) {
    const std::uint64_t* m = model.row(y);
    const std::uint64_t* s = silhouette.row(y);
    const std::uint64_t* h = hidden ? hidden->row(y) : nullptr;
    for (int w = 0; w < words; ++w) {
      const std::uint64_t differ = (m[w] ^ s[w]) & (h ? ~h[w] : ~std::uint64_t{0});
      n += std::popcount(differ);
    }
  }
  return n;
}

}  // namespace spinewatch::cvsm_detail
