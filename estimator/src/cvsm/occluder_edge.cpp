#include "cvsm/occluder_edge.hpp"

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

// Least-squares line through the run's lowest pixels, fitted again
// without those farther than kEdgeResidualPx from it; nothing when more
// than kEdgeOutlierShare of them are (a curve, not an edge: a pixel of
// noise or a fold of the shirt on the edge is allowed) or it is too steep.
std::optional<OccluderEdge> straight(const std::vector<int>& bottom, int x0, int x1) {
  OccluderEdge e{x0, x1, 0, 0, x0, x1};
  auto fit = [&](bool inliers_only) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int x = x0; x <= x1; ++x) {
      const double u = x - x0, y = bottom[static_cast<std::size_t>(x)];
      if (inliers_only && std::abs(y - e.row(x)) > kEdgeResidualPx) continue;
      n += 1;
      sx += u;
      sy += y;
      sxx += u * u;
      sxy += u * y;
    }
    const double det = n * sxx - sx * sx;
    if (det <= 0) return false;
    e.slope = (n * sxy - sx * sy) / det;
    e.row_at_x0 = (sy - e.slope * sx) / n;
    return true;
  };
  if (!fit(false) || !fit(true)) return std::nullopt;
  if (std::abs(e.slope) > kEdgeSlope) return std::nullopt;
  int outliers = 0;
  for (int x = x0; x <= x1; ++x) outliers += std::abs(bottom[static_cast<std::size_t>(x)] - e.row(x)) > kEdgeResidualPx;
  if (outliers > kEdgeOutlierShare * (x1 - x0 + 1)) return std::nullopt;
  return e;
}

// The straight part of a run: the run itself, or it shortened from
// whichever end strays farther from its line (a thigh's straight underside
// running into the rounded buttock), down to kEdgeMinColumns.
std::optional<OccluderEdge> straightest(const std::vector<int>& bottom, int x0, int x1) {
  while (x1 - x0 + 1 >= kEdgeMinColumns) {
    if (auto e = straight(bottom, x0, x1)) return e;
    // The end farther from the middle's row goes.
    const double centre = bottom[static_cast<std::size_t>((x0 + x1) / 2)];
    const double left = std::abs(bottom[static_cast<std::size_t>(x0)] - centre);
    const double right = std::abs(bottom[static_cast<std::size_t>(x1)] - centre);
    if (left > right)
      ++x0;
    else
      --x1;
  }
  return std::nullopt;
}

// The columns an edge hides: the span's and a quarter of the straight
// run's width beyond each end (an occluder is wider than the part of the
// person it cuts).
std::pair<int, int> hidden_columns(const OccluderEdge& e, int width, HiddenSpan span = HiddenSpan::Run) {
  const int pad = (e.x1 - e.x0 + 1) / 4;
  const bool cut = span == HiddenSpan::Cut;
  return {std::max(0, (cut ? e.cut_x0 : e.x0) - pad), std::min(width - 1, (cut ? e.cut_x1 : e.x1) + pad)};
}

// From the run outwards along the edge's line, the outermost column (on
// the side `step` walks) whose lowest pixel lies on the line within
// kEdgeBelowPx; the walk stops at a column whose silhouette reaches
// farther below it (an arm hanging past the desk's edge: not cut there).
int last_cut_column(const std::vector<int>& bottom, const OccluderEdge& e, int from, int step) {
  int cut = from;
  for (int x = from + step; x >= 0 && x < static_cast<int>(bottom.size()); x += step) {
    const int b = bottom[static_cast<std::size_t>(x)];
    if (b < 0) continue;
    if (b > e.row(x) + kEdgeBelowPx) break;
    if (b >= e.row(x) - kEdgeBelowPx) cut = x;
  }
  return cut;
}

// Whether the person ends at the edge: no silhouette more than
// kEdgeBelowPx below it on the columns it hides (hands resting on the
// desk's top reach a pixel or two lower). A body's own straight outline
// does not end the person (a seated thigh's underside has the shank going
// down from its end).
bool nothing_below(const std::vector<int>& bottom, const OccluderEdge& e) {
  const auto [lo, hi] = hidden_columns(e, static_cast<int>(bottom.size()));
  for (int x = lo; x <= hi; ++x)
    if (bottom[static_cast<std::size_t>(x)] > e.row(x) + kEdgeBelowPx) return false;
  return true;
}

}  // namespace

std::optional<OccluderEdge> find_occluder_edge(const BitMask& silhouette, double floor_row) {
  const LowerOutline o = lower_outline(silhouette);
  if (o.top < 0) return std::nullopt;
  // How wide the person is just above a candidate edge: the edge must cut
  // most of that (the trunk), not one hand or one shoe.
  auto wide_enough = [&](const OccluderEdge& e) {
    const int above = static_cast<int>(std::lround(e.row((e.x0 + e.x1) / 2))) - kEdgeAbovePx;
    const auto person = above >= 0 && above < silhouette.height() ? silhouette.count_row(above) : 0;
    return e.x1 - e.x0 + 1 >= kEdgeWidthShare * static_cast<double>(person);
  };
  // The image's own lower border is no occluder: the cost sees nothing
  // beyond it anyway.
  auto above_border = [&](const OccluderEdge& e) {
    return std::max(e.row(e.x0), e.row(e.x1)) < silhouette.height() - 1 - kEdgeResidualPx;
  };
  // Where the person ends: an edge higher up is a body part's own outline
  // (an arm held out sideways is straight underneath, with the legs far
  // below it).
  const int lowest = *std::max_element(o.bottom.begin(), o.bottom.end());
  auto at_the_end = [&](const OccluderEdge& e) { return std::max(e.row(e.x0), e.row(e.x1)) >= lowest - kEdgeBelowPx; };
  // Runs of columns along which the lower outline moves at most a pixel a
  // column: a candidate straight edge each.
  std::optional<OccluderEdge> best;
  const int last = silhouette.width() - 1;
  int x = 0;
  while (x <= last) {
    int end = x;
    while (end + 1 <= last && o.bottom[static_cast<std::size_t>(end + 1)] >= 0 && o.bottom[static_cast<std::size_t>(x)] >= 0 &&
           std::abs(o.bottom[static_cast<std::size_t>(end + 1)] - o.bottom[static_cast<std::size_t>(end)]) <= 1)
      ++end;
    if (o.bottom[static_cast<std::size_t>(x)] >= 0 && end - x + 1 >= kEdgeMinColumns && (!best || end - x > best->x1 - best->x0)) {
      if (auto e = straightest(o.bottom, x, end); e && above_border(*e) && at_the_end(*e) && nothing_below(o.bottom, *e) && wide_enough(*e) &&
                                                   (!best || e->x1 - e->x0 > best->x1 - best->x0))
        best = e;
    }
    x = end + 1;
  }
  if (!best) return std::nullopt;
  const double edge_row = best->row((best->x0 + best->x1) / 2);
  const double person_rows = floor_row - o.top;
  if (person_rows <= 0 || floor_row - edge_row <= kEdgeAboveFloorShare * person_rows) return std::nullopt;
  best->cut_x0 = last_cut_column(o.bottom, *best, best->x0, -1);
  best->cut_x1 = last_cut_column(o.bottom, *best, best->x1, +1);
  return best;
}

void hidden_below(const OccluderEdge& edge, const BitMask& silhouette, BitMask& out, HiddenSpan span) {
  if (out.width() != silhouette.width() || out.height() != silhouette.height())
    out = BitMask(silhouette.width(), silhouette.height());
  else
    out.clear();
  const auto [lo, hi] = hidden_columns(edge, silhouette.width(), span);
  for (int x = lo; x <= hi; ++x) {
    const int from = std::max(0, static_cast<int>(std::floor(edge.row(x))) + 1);
    for (int y = from; y < silhouette.height(); ++y)
      if (!silhouette.get(x, y)) out.set(x, y);
  }
}

}  // namespace spinewatch::cvsm_detail
