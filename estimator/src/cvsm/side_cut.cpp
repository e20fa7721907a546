#include "cvsm/side_cut.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "cvsm/occluder_edge.hpp"

namespace spinewatch::cvsm_detail {
namespace {

// The row's outermost set column on `side`, -1 for an empty row.
int outermost(const BitMask& m, int y, Side side) {
  const std::uint64_t* row = m.row(y);
  const int words = m.words_per_row();
  if (side == Side::Right) {
    for (int k = words - 1; k >= 0; --k)
      if (row[k]) return k * 64 + 63 - std::countl_zero(row[k]);
  } else {
    for (int k = 0; k < words; ++k)
      if (row[k]) return k * 64 + std::countr_zero(row[k]);
  }
  return -1;
}

// The least-squares line through rows y0 … y1's outermost columns.
SideCut fit_line(const std::vector<int>& end, int y0, int y1, Side side) {
  double n = 0, sv = 0, sx = 0, svv = 0, svx = 0;
  for (int y = y0; y <= y1; ++y) {
    const double v = y - y0, x = end[static_cast<std::size_t>(y)];
    n += 1;
    sv += v;
    sx += x;
    svv += v * v;
    svx += v * x;
  }
  SideCut cut{side, y0, y1, 0, 0};
  const double det = n * svv - sv * sv;
  cut.slope = det > 0 ? (n * svx - sv * sx) / det : 0;
  cut.column_at_y0 = (sx - cut.slope * sv) / n;
  return cut;
}

// The run's straight part: its line, trimmed row by row from the end
// that lies farther from it until every row lies within kEdgeResidualPx
// (where the thing's edge bends — a desk's corner — the straight part
// is the edge's side); nothing when fewer than kSideCutMinRows remain.
std::optional<SideCut> straight(const std::vector<int>& end, int y0, int y1, Side side) {
  while (y1 - y0 + 1 >= kSideCutMinRows) {
    const SideCut cut = fit_line(end, y0, y1, side);
    auto off = [&](int y) { return std::abs(end[static_cast<std::size_t>(y)] - cut.column(y)); };
    double worst = 0;
    for (int y = y0; y <= y1; ++y) worst = std::max(worst, off(y));
    if (worst <= kEdgeResidualPx) return cut;
    if (off(y0) >= off(y1))
      ++y0;
    else
      --y1;
  }
  return std::nullopt;
}

}  // namespace

std::optional<SideCut> find_side_cut(const BitMask& silhouette, const BitMask& scene_edge, Side side) {
  const int h = silhouette.height();
  if (silhouette.empty() || scene_edge.width() != silhouette.width() || scene_edge.height() != h) return std::nullopt;
  std::vector<int> end(static_cast<std::size_t>(h), -1);
  int top = -1, bottom = -1;
  for (int y = 0; y < h; ++y) {
    end[static_cast<std::size_t>(y)] = outermost(silhouette, y, side);
    if (end[static_cast<std::size_t>(y)] < 0) continue;
    if (top < 0) top = y;
    bottom = y;
  }
  if (top < 0) return std::nullopt;
  std::optional<SideCut> best;
  int run_start = -1;
  auto close_run = [&](int last) {
    if (run_start < 0) return;
    if (last - run_start + 1 >= kSideCutMinRows && (!best || last - run_start > best->y1 - best->y0))
      if (auto cut = straight(end, run_start, last, side)) best = cut;
    run_start = -1;
  };
  for (int y = top + (bottom - top) / 2; y <= bottom; ++y) {
    const int x = end[static_cast<std::size_t>(y)];
    const bool on_edge = x >= 0 && scene_edge.get(x, y);
    const bool continues = run_start >= 0 && std::abs(x - end[static_cast<std::size_t>(y - 1)]) <= 1;
    if (on_edge && continues) continue;
    close_run(y - 1);
    if (on_edge) run_start = y;
  }
  close_run(bottom);
  return best;
}

void add_hidden_beyond(const SideCut& cut, const BitMask& silhouette, BitMask& out) {
  const int w = silhouette.width(), h = silhouette.height();
  const int margin = (cut.y1 - cut.y0 + 1) / 4;
  for (int y = std::max(0, cut.y0 - margin); y <= std::min(h - 1, cut.y1 + margin); ++y) {
    const double line = cut.column(y);
    const int x0 = cut.side == Side::Right ? static_cast<int>(std::floor(line)) + 1 : 0;
    const int x1 = cut.side == Side::Right ? w - 1 : static_cast<int>(std::ceil(line)) - 1;
    if (x0 > x1) continue;
    out.set_span(y, x0, x1);
    // Never a silhouette pixel: the person seen there is counted.
    std::uint64_t* row = out.row(y);
    const std::uint64_t* person = silhouette.row(y);
    for (int k = 0; k < out.words_per_row(); ++k) row[k] &= ~person[k];
  }
}

}  // namespace spinewatch::cvsm_detail
