#include "cvsm/lower_residual.hpp"

#include <algorithm>
#include <bit>

namespace spinewatch::cvsm_detail {

namespace {

// Pixels on rows first_row … the last where `kept(model word, silhouette
// word)` is set and `hidden` is not.
template <class Kept>
std::int64_t count_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden, int first_row,
                         Kept kept) {
  std::int64_t n = 0;
  const int words = model.words_per_row();
  for (int y = std::max(0, first_row); y < model.height(); ++y) {
    const std::uint64_t* m = model.row(y);
    const std::uint64_t* s = silhouette.row(y);
    const std::uint64_t* h = hidden ? hidden->row(y) : nullptr;
    for (int w = 0; w < words; ++w) {
      n += std::popcount(kept(m[w], s[w]) & (h ? ~h[w] : ~std::uint64_t{0}));
    }
  }
  return n;
}

}  // namespace

std::int64_t xor_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden, int first_row) {
  return count_below(model, silhouette, hidden, first_row, [](std::uint64_t m, std::uint64_t s) { return m ^ s; });
}

std::int64_t silhouette_outside_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden,
                                      int first_row) {
  return count_below(model, silhouette, hidden, first_row, [](std::uint64_t m, std::uint64_t s) { return s & ~m; });
}

}  // namespace spinewatch::cvsm_detail
