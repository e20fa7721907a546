#pragma once
// Where a view's silhouette ends on the edge of something in front of the
// person (a desk, a counter, a machine) rather than where the person ends
// (docs/cvsm.md, "Occluded lower body"). The stored background holds the
// occluder, so the person behind it is cut on the occluder's outline: the
// silhouette's lower outline runs along a straight edge across most of the
// person's width, high above the floor the person stands or sits on. Below
// that edge the views say nothing about the body, and the fit's cost must
// not count the model's parts there.
#include <optional>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

struct OccluderEdge {
  int x0 = 0, x1 = 0;             // columns the straight lower outline spans
  double row_at_x0 = 0, slope = 0;  // the edge's row at x0, rows per column
  double row(int x) const { return row_at_x0 + slope * (x - x0); }
};

// The widest straight stretch of the silhouette's lower outline (a run of
// columns whose lowest pixel lies on one line, within kEdgeResidualPx but
// for kEdgeOutlierShare of them, at most kEdgeSlope steep) with no silhouette below it, when it spans at
// least kEdgeWidthShare of the silhouette's pixels on the row kEdgeAbovePx
// above it (the trunk it cuts, not a hand or a shoe beside the trunk),
// reaches down to within kEdgeBelowPx of the silhouette's lowest row
// (where the person ends, not an arm held out above the legs)
// and lies above `floor_row` (the row where the floor
// under the person projects) by more than kEdgeAboveFloorShare of the
// person's height in the image. Nothing otherwise: feet on the floor, a
// body ending on its own rounded outline.
std::optional<OccluderEdge> find_occluder_edge(const BitMask& silhouette, double floor_row);

// The pixels the occluder hides: below the edge, on its columns and a
// quarter of its width beyond each end, that are not silhouette. `out` is
// resized to the silhouette's size.
void hidden_below(const OccluderEdge& edge, const BitMask& silhouette, BitMask& out);

inline constexpr double kEdgeResidualPx = 1.5;
inline constexpr double kEdgeOutlierShare = 0.1;
inline constexpr double kEdgeSlope = 0.5;
inline constexpr double kEdgeWidthShare = 0.4;
inline constexpr double kEdgeAboveFloorShare = 0.15;
inline constexpr int kEdgeMinColumns = 12;
inline constexpr int kEdgeAbovePx = 3;
inline constexpr double kEdgeBelowPx = 4;

}  // namespace spinewatch::cvsm_detail
