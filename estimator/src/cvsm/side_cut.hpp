#pragma once
// Where a view's silhouette ends on the side of something in front of the
// person rather than where the person ends (docs/cvsm.md, "A desk's
// side"). Seen from the side, a worker's thighs go under the desk and are
// cut by its end on a steep line; the lower outline's occluder
// (occluder_edge.hpp), a near-level line across the trunk, is not it. The
// stored background holds the desk, so the outline there runs along the
// desk's own edge (SilhouetteResult::scene_edge) row after row, on a
// straight line; beyond that line the view says nothing about the body,
// and the fit's cost must not count the model's parts there (the thighs a
// tall worker's model draws under the desk).
#include <optional>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

enum class Side { Left, Right };

struct SideCut {
  Side side = Side::Right;
  int y0 = 0, y1 = 0;                  // the rows the straight side outline spans
  double column_at_y0 = 0, slope = 0;  // the line's column at y0, columns per row
  double column(int y) const { return column_at_y0 + slope * (y - y0); }
};

// The longest run of rows in the lower half of the silhouette (the lower
// body: the head and the trunk's sides above it end on the person) whose
// outermost pixel on `side` is a scene edge, each row's within one column
// of the row's above (a line within 45° of the vertical), every pixel
// within kEdgeResidualPx of the run's least-squares line; at least
// kSideCutMinRows rows. Nothing otherwise: an outline on a plain wall, a
// rounded knee.
std::optional<SideCut> find_side_cut(const BitMask& silhouette, const BitMask& scene_edge, Side side);

// Adds to `out` (the silhouette's size) the pixels beyond the cut's line
// on its side, on its rows and a quarter of its length above and below,
// that are not silhouette: where the thing in front hides the body.
void add_hidden_beyond(const SideCut& cut, const BitMask& silhouette, BitMask& out);

// Rows of straight outline on the scene's edge that make a cut: a thigh
// seen from the side at 2–3 m is 12–20 rows thick.
inline constexpr int kSideCutMinRows = 8;

}  // namespace spinewatch::cvsm_detail
