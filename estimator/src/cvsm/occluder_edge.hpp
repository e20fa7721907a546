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
  // The outermost columns on each side where the silhouette still ends on
  // the edge's line (x0 and x1 when nowhere beyond them): the occluder's
  // edge is one straight line, and it cuts whatever of the person ends on
  // it, beside the trunk too (forearms resting on the desk, past a gap of
  // background under the armpit that breaks the straight run).
  int cut_x0 = 0, cut_x1 = 0;
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
// body ending on its own rounded outline. cut_x0/cut_x1 are widened from
// the run along the line to the outermost columns whose lowest pixel lies
// within kEdgeBelowPx of it, never across a column whose silhouette
// reaches farther below it (something the occluder does not hide).
std::optional<OccluderEdge> find_occluder_edge(const BitMask& silhouette, double floor_row);

// Which columns hidden_below() takes: the straight run's (x0 … x1), or
// all those the edge cuts the person on (cut_x0 … cut_x1).
enum class HiddenSpan { Run, Cut };

// The pixels the occluder hides: below the edge's line, on the span's
// columns and a quarter of the straight run's width beyond each end, that
// are not silhouette. `out` is resized to the silhouette's size. The fit
// hides the run's span: where the arms end on the edge (hands reaching to
// a bench, `reach`) their ends place the arms, and with the cut span
// hidden while tracking, ANSUR 28496 reaching to the bench had 4 postures
// 50–55 mm off (docs/cvsm.md, "Occluded lower body"). The standing-or-
// seated choice hides the cut span (cvsm/posture_hidden.hpp).
void hidden_below(const OccluderEdge& edge, const BitMask& silhouette, BitMask& out, HiddenSpan span = HiddenSpan::Run);

inline constexpr double kEdgeResidualPx = 1.5;
inline constexpr double kEdgeOutlierShare = 0.1;
inline constexpr double kEdgeSlope = 0.5;
inline constexpr double kEdgeWidthShare = 0.4;
inline constexpr double kEdgeAboveFloorShare = 0.15;
inline constexpr int kEdgeMinColumns = 12;
inline constexpr int kEdgeAbovePx = 3;
inline constexpr double kEdgeBelowPx = 4;

}  // namespace spinewatch::cvsm_detail
