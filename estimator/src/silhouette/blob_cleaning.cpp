// Cleaning on packed rows: morphology with shifts, connected components on
// runs (a person's row has a handful of runs, so labelling runs instead of
// pixels costs next to nothing).
#include <algorithm>
#include <numeric>
#include <vector>

#include "silhouette/blob_fragments.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"

namespace spinewatch {
namespace {

// Horizontal 3-pixel dilation (op = or) or erosion (op = and) of one row.
template <bool Dilate>
void horizontal(const std::uint64_t* src, std::uint64_t* dst, int words) {
  for (int w = 0; w < words; ++w) {
    const std::uint64_t prev = w > 0 ? src[w - 1] : (Dilate ? 0 : ~std::uint64_t{0});
    const std::uint64_t next = w + 1 < words ? src[w + 1] : (Dilate ? 0 : ~std::uint64_t{0});
    const std::uint64_t left = (src[w] << 1) | (prev >> 63);   // pixel x−1 at bit x
    const std::uint64_t right = (src[w] >> 1) | (next << 63);  // pixel x+1 at bit x
    dst[w] = Dilate ? (src[w] | left | right) : (src[w] & left & right);
  }
}

// Cross-shaped dilation or erosion of `in` into `out` (same size);
// outside the image counts as background for dilation and as foreground
// for erosion (so erosion does not eat blobs that touch the border).
template <bool Dilate>
void cross(const BitMask& in, BitMask& out) {
  const int words = in.words_per_row();
  constexpr std::uint64_t kOutside = Dilate ? 0 : ~std::uint64_t{0};
  const std::vector<std::uint64_t> outside(static_cast<std::size_t>(words), kOutside);
  const std::uint64_t keep = (in.width() & 63) != 0 ? (std::uint64_t{1} << (in.width() & 63)) - 1 : ~std::uint64_t{0};
  for (int y = 0; y < in.height(); ++y) {
    const std::uint64_t* up = y > 0 ? in.row(y - 1) : outside.data();
    const std::uint64_t* down = y + 1 < in.height() ? in.row(y + 1) : outside.data();
    const std::uint64_t* mid = in.row(y);
    std::uint64_t* dst = out.row(y);
    horizontal<Dilate>(mid, dst, words);
    for (int w = 0; w < words; ++w) dst[w] = Dilate ? (dst[w] | up[w] | down[w]) : (dst[w] & up[w] & down[w]);
    dst[words - 1] &= keep;  // the padding bits stay clear
  }
}

struct Run {
  int y, x0, x1;
  int parent;
};

int find(std::vector<Run>& runs, int i) {
  while (runs[static_cast<std::size_t>(i)].parent != i) {
    auto& r = runs[static_cast<std::size_t>(i)];
    r.parent = runs[static_cast<std::size_t>(r.parent)].parent;
    i = r.parent;
  }
  return i;
}

// Appends the runs of set bits of row y.
void row_runs(const BitMask& mask, int y, std::vector<Run>& runs) {
  const std::uint64_t* row = mask.row(y);
  const int words = mask.words_per_row();
  int x = 0;
  const int width = mask.width();
  while (x < width) {
    // Next set bit at or after x.
    int w = x >> 6;
    std::uint64_t bits = row[w] & (~std::uint64_t{0} << (x & 63));
    while (bits == 0 && ++w < words) bits = row[w];
    if (w >= words) return;
    const int start = w * 64 + std::countr_zero(bits);
    // Next clear bit after start.
    w = start >> 6;
    std::uint64_t clear = ~row[w] & (~std::uint64_t{0} << (start & 63));
    while (clear == 0 && ++w < words) clear = ~row[w];
    const int end = w >= words ? width : std::min(width, w * 64 + std::countr_zero(clear));
    const int id = static_cast<int>(runs.size());
    runs.push_back({y, start, end - 1, id});
    x = end;
  }
}

}  // namespace

void close_cross(BitMask& mask) {
  BitMask dilated(mask.width(), mask.height());
  cross<true>(mask, dilated);
  cross<false>(dilated, mask);
}

void open_square(BitMask& mask, int radius) {
  if (mask.empty()) return;
  const int words = mask.words_per_row();
  const int width = mask.width();
  const std::uint64_t keep = (width & 63) != 0 ? (std::uint64_t{1} << (width & 63)) - 1 : ~std::uint64_t{0};
  auto invert = [&](BitMask& m) {
    for (int y = 0; y < m.height(); ++y) {
      std::uint64_t* row = m.row(y);
      for (int w = 0; w < words; ++w) row[w] = ~row[w];
      row[words - 1] &= keep;
    }
  };
  // Eroded: the complement of the complement grown (pixels beyond the
  // image are not in the complement, so they never erode).
  BitMask outside = mask, eroded(width, mask.height());
  invert(outside);
  dilate_square(outside, radius, eroded);
  invert(eroded);
  dilate_square(eroded, radius, mask);
}

BlobSummary keep_largest_blob(BitMask& mask, int min_px) {
  std::vector<Run> runs;
  runs.reserve(1024);
  std::size_t prev_begin = 0, prev_end = 0;
  for (int y = 0; y < mask.height(); ++y) {
    const std::size_t begin = runs.size();
    row_runs(mask, y, runs);
    const std::size_t end = runs.size();
    // Both run lists are sorted by x: merge-walk them, joining 8-connected runs.
    std::size_t p = prev_begin;
    for (std::size_t i = begin; i < end; ++i) {
      while (p < prev_end && runs[p].x1 + 1 < runs[i].x0) ++p;
      for (std::size_t q = p; q < prev_end && runs[q].x0 <= runs[i].x1 + 1; ++q) {
        const int a = find(runs, static_cast<int>(i)), b = find(runs, static_cast<int>(q));
        if (a != b) runs[static_cast<std::size_t>(std::max(a, b))].parent = std::min(a, b);
      }
    }
    prev_begin = begin;
    prev_end = end;
  }
  std::vector<std::int64_t> area(runs.size(), 0);
  for (std::size_t i = 0; i < runs.size(); ++i)
    area[static_cast<std::size_t>(find(runs, static_cast<int>(i)))] += runs[i].x1 - runs[i].x0 + 1;

  BlobSummary s;
  int best = -1;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].parent != static_cast<int>(i)) continue;
    if (area[i] >= min_px) ++s.blobs;
    if (area[i] > s.largest_px) {
      s.largest_px = area[i];
      best = static_cast<int>(i);
    }
  }
  mask.clear();
  if (best < 0) return s;
  // Which blobs are kept: the largest and its fragments (blob_fragments.hpp).
  std::vector<silhouette_detail::BlobBox> boxes(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i)
    boxes[static_cast<std::size_t>(find(runs, static_cast<int>(i)))].add(runs[i].y, runs[i].x0, runs[i].x1);
  std::vector<bool> kept(runs.size(), false);
  kept[static_cast<std::size_t>(best)] = true;
  const silhouette_detail::BlobBox& subject = boxes[static_cast<std::size_t>(best)];
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].parent != static_cast<int>(i) || static_cast<int>(i) == best) continue;
    if (area[i] >= min_px && silhouette_detail::is_fragment_of(boxes[i], subject)) {
      kept[i] = true;
      s.largest_px += area[i];
      ++s.fragments;
    } else if (area[i] > s.second_px) {
      s.second_px = area[i];
    }
  }
  s.x_min = mask.width();
  s.y_min = mask.height();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!kept[static_cast<std::size_t>(find(runs, static_cast<int>(i)))]) continue;
    const Run& r = runs[i];
    set_bits(mask.row(r.y), r.x0, r.x1);
    s.x_min = std::min(s.x_min, r.x0);
    s.x_max = std::max(s.x_max, r.x1);
    s.y_min = std::min(s.y_min, r.y);
    s.y_max = std::max(s.y_max, r.y);
  }
  return s;
}

}  // namespace spinewatch
