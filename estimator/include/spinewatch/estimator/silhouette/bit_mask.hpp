#pragma once
// A binary image packed one bit per pixel, rows padded to whole 64-bit
// words (a 320-pixel row is five words). Bit x of a row lives in word x / 64
// at bit x % 64, so a run of pixels is a run of bits in reading order.
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

namespace spinewatch {

class BitMask {
 public:
  BitMask() = default;
  BitMask(int width, int height)
      : width_(width), height_(height), words_per_row_((width + 63) / 64),
        words_(static_cast<std::size_t>(words_per_row_) * static_cast<std::size_t>(height), 0) {}

  int width() const { return width_; }
  int height() const { return height_; }
  int words_per_row() const { return words_per_row_; }
  bool empty() const { return words_.empty(); }

  std::uint64_t* row(int y) { return words_.data() + static_cast<std::ptrdiff_t>(y) * words_per_row_; }
  const std::uint64_t* row(int y) const { return words_.data() + static_cast<std::ptrdiff_t>(y) * words_per_row_; }

  bool get(int x, int y) const { return (row(y)[x >> 6] >> (x & 63)) & 1U; }
  void set(int x, int y, bool on = true) {
    const std::uint64_t bit = std::uint64_t{1} << (x & 63);
    if (on)
      row(y)[x >> 6] |= bit;
    else
      row(y)[x >> 6] &= ~bit;
  }
  // Sets pixels x0..x1 inclusive of row y (clipped to the row).
  void set_span(int y, int x0, int x1);
  void clear() { std::fill(words_.begin(), words_.end(), 0); }

  std::int64_t count() const;
  std::int64_t count_row(int y) const;
  bool operator==(const BitMask&) const = default;

 private:
  int width_ = 0, height_ = 0, words_per_row_ = 0;
  std::vector<std::uint64_t> words_;
};

// Sets bits x0..x1 (inclusive, already clipped to the row) in a packed row.
inline void set_bits(std::uint64_t* row, int x0, int x1) {
  int w0 = x0 >> 6, w1 = x1 >> 6;
  const std::uint64_t first = ~std::uint64_t{0} << (x0 & 63);
  const std::uint64_t last = ~std::uint64_t{0} >> (63 - (x1 & 63));
  if (w0 == w1) {
    row[w0] |= first & last;
    return;
  }
  row[w0] |= first;
  for (int w = w0 + 1; w < w1; ++w) row[w] = ~std::uint64_t{0};
  row[w1] |= last;
}

}  // namespace spinewatch
