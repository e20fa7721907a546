#include "spinewatch/estimator/cvsm/edge_fractions.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch::cvsm_detail {

void EdgeFractions::reset(int height, int segments) {
  if (height != height_ || segments > capacity_) {
    height_ = height;
    capacity_ = std::max(segments, capacity_);
    spans_.assign(static_cast<std::size_t>(height_) * static_cast<std::size_t>(capacity_), Span{});
    count_.assign(static_cast<std::size_t>(height_), 0);
  } else if (y_lo_ <= y_hi_) {
    std::fill(count_.begin() + y_lo_, count_.begin() + y_hi_ + 1, 0);
  }
  y_lo_ = height_;
  y_hi_ = -1;
}

void EdgeFractions::add(int first, int count, int step, const float* left, const float* right) {
  for (int i = 0; i < count; ++i) {
    if (right[i] < left[i]) continue;
    const int y = first + i * step;
    int& n = count_[static_cast<std::size_t>(y)];
    Span* row = spans_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(capacity_);
    // Segments come chain by chain, and neighbours along a chain overlap on
    // the rows they share: merged here, the trunk's dozen spans on a row
    // become one or two, and the sort below has little to do.
    if (n > 0 && left[i] <= row[n - 1].right && right[i] >= row[n - 1].left) {
      row[n - 1] = {std::min(left[i], row[n - 1].left), std::max(right[i], row[n - 1].right)};
    } else {
      row[n++] = {left[i], right[i]};
    }
    y_lo_ = std::min(y_lo_, y);
    y_hi_ = std::max(y_hi_, y);
  }
}

double EdgeFractions::correction(const std::uint64_t* model, int words, const BitMask& silhouette) {
  const int width = silhouette.width();
  const auto edge = static_cast<float>(width - 1);
  double sum = 0;
  for (int y = y_lo_; y <= y_hi_; ++y) {
    const int n = count_[static_cast<std::size_t>(y)];
    if (n == 0) continue;
    Span* row = spans_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(capacity_);
    // A handful of spans a row (trunk, arms, legs): insertion sort, in place.
    for (int i = 1; i < n; ++i)
      for (int j = i; j > 0 && row[j].left < row[j - 1].left; --j) std::swap(row[j], row[j - 1]);
    const std::uint64_t* bits = model + static_cast<std::ptrdiff_t>(y) * words;
    const std::uint64_t* sil = silhouette.row(y);
    // Pixel q covered by c of its width: its XOR term goes from |b − s|
    // (b: its centre is inside) to |c − s|, i.e. changes by (c − b) off
    // the silhouette and by (b − c) on it.
    int pending_q = -1;
    float pending_c = 0;
    auto flush = [&] {
      if (pending_q < 0) return;
      const float c = std::min(pending_c, 1.0f);
      const bool b = (bits[pending_q >> 6] >> (pending_q & 63)) & 1u;
      const bool s = (sil[pending_q >> 6] >> (pending_q & 63)) & 1u;
      const float change = c - (b ? 1.0f : 0.0f);
      sum += s ? -change : change;
      pending_q = -1;
    };
    auto cover = [&](int q, float c) {
      if (q != pending_q) {
        flush();
        pending_q = q;
        pending_c = 0;
      }
      pending_c += c;
    };
    // Runs of the union, in order, each ending in at most two pixels
    // (one when it lies within a pixel); an end clamped to the image's
    // edge covers its pixel whole.
    auto run = [&](float left, float right) {
      const int ql = std::clamp(static_cast<int>(std::floor(left + 0.5f)), 0, width - 1);
      const int qr = std::clamp(static_cast<int>(std::floor(right + 0.5f)), 0, width - 1);
      const bool open_left = left > 0.0f, open_right = right < edge;
      if (ql == qr) {
        if (open_left || open_right)
          cover(ql, (open_right ? right : static_cast<float>(qr) + 0.5f) - (open_left ? left : static_cast<float>(ql) - 0.5f));
        return;
      }
      if (open_left) cover(ql, static_cast<float>(ql) + 0.5f - left);
      if (open_right) cover(qr, right - (static_cast<float>(qr) - 0.5f));
    };
    float left = row[0].left, right = row[0].right;
    for (int i = 1; i < n; ++i) {
      if (row[i].left <= right) {
        right = std::max(right, row[i].right);
        continue;
      }
      run(left, right);
      left = row[i].left;
      right = row[i].right;
    }
    run(left, right);
    flush();
  }
  return sum;
}

}  // namespace spinewatch::cvsm_detail
