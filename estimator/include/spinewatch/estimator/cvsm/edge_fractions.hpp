#pragma once
// The part of the fit's cost that the pixel grid hides: how much the
// exclusive-or changes when the model covers the pixels its outline runs
// through by the fraction it covers, instead of all or nothing by their
// centres. A detail of XorCost::evaluate_fractional, public for its tests.
//
// Why: counted in whole pixels (about 6.7 mm at 2 m), the cost is a
// staircase in the pose, and a search settles on whichever stair its path
// reaches; a hundredth of a pixel in a camera's calibration moves which
// one, and the postures by millimetres (docs/cvsm.md, "Sub-pixel
// refinement"). With the outline's pixels covered in fractions the cost
// changes continuously as a span end moves along its row, and a
// refinement can settle between the stairs.
//
// Only along rows: the rows are still sampled at their centres, so a
// horizontal edge (the top of the head) still moves the cost by whole rows.
#include <cstdint>
#include <vector>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

class EdgeFractions {
 public:
  // Starts a view: rows 0 … height − 1, at most `segments` spans a row.
  void reset(int height, int segments);
  // One segment's continuous spans: row first + i·step (i < count) has
  // left[i] ≤ x ≤ right[i] (empty when right < left).
  void add(int first, int count, int step, const float* left, const float* right);
  // The change of the XOR count, summed over the rows added, against the
  // model's rows as set by pixel centre (`model`, `words` per row) and the
  // silhouette. The pixels a span end falls in are covered by the union of
  // the spans there; a span reaching the image's edge covers its last
  // pixel whole, as the centre rule does.
  // Sorts each row's spans in place: once per reset().
  double correction(const std::uint64_t* model, int words, const BitMask& silhouette);

 private:
  struct Span {
    float left, right;
  };
  int height_ = 0, capacity_ = 0;
  std::vector<Span> spans_;       // height × capacity
  std::vector<int> count_;        // spans per row
  int y_lo_ = 0, y_hi_ = -1;      // rows with spans
};

}  // namespace spinewatch::cvsm_detail
