#include "occluder_edge.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>
#include <vector>

namespace spinewatch::cvsm_detail {
namespace {

// Per column, the silhouette's lowest row (-1: an empty column), and its
// highest row overall.
struct LowerOutline {
  std::vector<int> bottom;
  int top = -1;
};
LowerOutline lower_outline(const BitMask& s) {
  LowerOutline o;
  o.bottom.assign(static_cast<std::size_t>(s.width()), -1);
  const int words = s.words_per_row();
  std::vector<std::uint64_t> seen(static_cast<std::size_t>(words), 0);
  for (int y = s.height() - 1; y >= 0; --y) {
    const std::uint64_t* row = s.row(y);
    for (int w = 0; w < words; ++w) {
      if (row[w]) o.top = y;
      std::uint64_t fresh = row[w] & ~seen[static_cast<std::size_t>(w)];
      seen[static_cast<std::size_t>(w)] |= row[w];
      while (fresh) {
        const int bit = std::countr_zero(fresh);
        fresh &= fresh - 1;
        o.bottom[static_cast<std::size_t>(64 * w + bit)] = y;
      }
    }
  }
  return o;
}

// Least-squares line through the run's lowest pixels; nothing when a pixel
// strays from it or it is too steep.
std::optional<OccluderEdge> straight(const std::vector<int>& bottom, int x0, int x1) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int x = x0; x <= x1; ++x) {
    const double u = x - x0, y = bottom[static_cast<std::size_t>(x)];
    n += 1;
    sx += u;
    sy += y;
    sxx += u * u;
    sxy += u * y;
  }
  const double det = n * sxx - sx * sx;
  if (det <= 0) return std::nullopt;
  OccluderEdge e{x0, x1, 0, 0};
  e.slope = (n * sxy - sx * sy) / det;
  e.row_at_x0 = (sy - e.slope * sx) / n;
  if (std::abs(e.slope) > kEdgeSlope) return std::nullopt;
  for (int x = x0; x <= x1; ++x)
    if (std::abs(bottom[static_cast<std::size_t>(x)] - e.row(x)) > kEdgeResidualPx) return std::nullopt;
  return e;
}

// The columns an edge hides: its own and a quarter of its width beyond
// each end (an occluder is wider than the part of the person it cuts).
std::pair<int, int> hidden_columns(const OccluderEdge& e, int width) {
  const int pad = (e.x1 - e.x0 + 1) / 4;
  return {std::max(0, e.x0 - pad), std::min(width - 1, e.x1 + pad)};
}

// Whether the person ends at the edge: no silhouette below it on the
// columns it hides. A body's own straight outline does not (a seated
// thigh's underside has the shank going down from its end).
bool nothing_below(const std::vector<int>& bottom, const OccluderEdge& e) {
  const auto [lo, hi] = hidden_columns(e, static_cast<int>(bottom.size()));
  for (int x = lo; x <= hi; ++x)
    if (bottom[static_cast<std::size_t>(x)] > e.row(x) + kEdgeResidualPx) return false;
  return true;
}

}  // namespace

std::optional<OccluderEdge> find_occluder_edge(const BitMask& silhouette, double floor_row) {
  const LowerOutline o = lower_outline(silhouette);
  if (o.top < 0) return std::nullopt;
  int first = -1, last = -1;
  for (int x = 0; x < silhouette.width(); ++x)
    if (o.bottom[static_cast<std::size_t>(x)] >= 0) {
      if (first < 0) first = x;
      last = x;
    }
  const int min_width = std::max(kEdgeMinColumns, static_cast<int>(std::ceil(kEdgeWidthShare * (last - first + 1))));
  // Runs of columns along which the lower outline moves at most a pixel a
  // column: a candidate straight edge each.
  std::optional<OccluderEdge> best;
  int x = first;
  while (x <= last) {
    int end = x;
    while (end + 1 <= last && o.bottom[static_cast<std::size_t>(end + 1)] >= 0 && o.bottom[static_cast<std::size_t>(x)] >= 0 &&
           std::abs(o.bottom[static_cast<std::size_t>(end + 1)] - o.bottom[static_cast<std::size_t>(end)]) <= 1)
      ++end;
    if (o.bottom[static_cast<std::size_t>(x)] >= 0 && end - x + 1 >= min_width && (!best || end - x > best->x1 - best->x0))
      if (auto e = straight(o.bottom, x, end); e && nothing_below(o.bottom, *e)) best = e;
    x = end + 1;
  }
  if (!best) return std::nullopt;
  const double edge_row = best->row((best->x0 + best->x1) / 2);
  const double person_rows = floor_row - o.top;
  if (person_rows <= 0 || floor_row - edge_row <= kEdgeAboveFloorShare * person_rows) return std::nullopt;
  return best;
}

void hidden_below(const OccluderEdge& edge, const BitMask& silhouette, BitMask& out) {
  if (out.width() != silhouette.width() || out.height() != silhouette.height())
    out = BitMask(silhouette.width(), silhouette.height());
  else
    out.clear();
  const auto [lo, hi] = hidden_columns(edge, silhouette.width());
  for (int x = lo; x <= hi; ++x) {
    const int from = std::max(0, static_cast<int>(std::floor(edge.row(x))) + 1);
    for (int y = from; y < silhouette.height(); ++y)
      if (!silhouette.get(x, y)) out.set(x, y);
  }
}

}  // namespace spinewatch::cvsm_detail
