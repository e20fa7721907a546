#pragma once
// The model's outline as a silhouette shows it: on each sampled row of a
// view, the two ends of every run of the union of the model's spans, each
// with the segment whose span reaches there. A detail of XorCost::outline,
// public for its tests.
//
// Why: the outline refinement (cvsm/outline_fit.hpp) moves the pose so that
// these ends meet the silhouette's edges. Their float positions move
// continuously with the pose, unlike the pixels the XOR counts, and the
// segment that bounds an end says which span to read again when a
// parameter is nudged (its derivative).
#include <cstdint>
#include <vector>

namespace spinewatch::cvsm_detail {

struct OutlineEnd {
  float x;               // pixels, pixel centres at integers
  std::int16_t row;
  std::uint8_t view;     // index_of(View)
  bool right;            // the run's right end (else its left)
  std::int32_t segment;  // the segment whose span ends here (XorCost's order)
};

class OutlineEnds {
 public:
  // Starts a view: rows 0 … height − 1, at most `segments` spans a row.
  void reset(int height, int segments);
  // One segment's spans: row first + i·step (i < count) has
  // left[i] ≤ x ≤ right[i] (empty when right < left).
  void add(int segment, int first, int count, int step, const float* left, const float* right);
  // Appends the runs' ends, row by row, each row's left to right.
  // Sorts each row's spans in place: once per reset().
  void collect(int view, std::vector<OutlineEnd>& out);

 private:
  struct Span {
    float left, right;
    std::int32_t left_segment, right_segment;
  };
  int height_ = 0, capacity_ = 0;
  std::vector<Span> spans_;   // height × capacity
  std::vector<int> count_;    // spans per row
  int y_lo_ = 0, y_hi_ = -1;  // rows with spans
};

}  // namespace spinewatch::cvsm_detail
