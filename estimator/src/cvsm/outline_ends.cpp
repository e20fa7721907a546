#include "cvsm/outline_ends.hpp"

#include <algorithm>
#include <utility>

namespace spinewatch::cvsm_detail {

void OutlineEnds::reset(int height, int segments) {
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

void OutlineEnds::add(int segment, int first, int count, int step, const float* left, const float* right) {
  for (int i = 0; i < count; ++i) {
    if (right[i] < left[i]) continue;
    const int y = first + i * step;
    int& n = count_[static_cast<std::size_t>(y)];
    Span* row = spans_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(capacity_);
    // Segments come chain by chain, and neighbours along a chain overlap on
    // the rows they share: merged here, the trunk's dozen spans on a row
    // become one or two, and the sort below has little to do.
    if (n > 0 && left[i] <= row[n - 1].right && right[i] >= row[n - 1].left) {
      Span& last = row[n - 1];
      if (left[i] < last.left) last.left = left[i], last.left_segment = segment;
      if (right[i] > last.right) last.right = right[i], last.right_segment = segment;
    } else {
      row[n++] = {left[i], right[i], segment, segment};
    }
    y_lo_ = std::min(y_lo_, y);
    y_hi_ = std::max(y_hi_, y);
  }
}

void OutlineEnds::collect(int view, std::vector<OutlineEnd>& out) {
  for (int y = y_lo_; y <= y_hi_; ++y) {
    const int n = count_[static_cast<std::size_t>(y)];
    if (n == 0) continue;
    Span* row = spans_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(capacity_);
    // A handful of spans a row (trunk, arms, legs): insertion sort, in place.
    for (int i = 1; i < n; ++i)
      for (int j = i; j > 0 && row[j].left < row[j - 1].left; --j) std::swap(row[j], row[j - 1]);
    auto emit = [&](const Span& run) {
      out.push_back({run.left, static_cast<std::int16_t>(y), static_cast<std::uint8_t>(view), false, run.left_segment});
      out.push_back({run.right, static_cast<std::int16_t>(y), static_cast<std::uint8_t>(view), true, run.right_segment});
    };
    Span run = row[0];
    for (int i = 1; i < n; ++i) {
      if (row[i].left <= run.right) {
        if (row[i].right > run.right) run.right = row[i].right, run.right_segment = row[i].right_segment;
        continue;
      }
      emit(run);
      run = row[i];
    }
    emit(run);
  }
}

}  // namespace spinewatch::cvsm_detail
