#pragma once
// Where a silhouette's rows change from background to person and back, for
// the outline refinement (cvsm/outline_fit.hpp): the edge a model outline
// end is pulled to is the nearest one of its kind on its row.
#include <cmath>
#include <limits>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

class SilhouetteEdges {
 public:
  // Edges between pixels inside the image only: a person cut off by the
  // image's edge has no edge there to be pulled to.
  void assign(const BitMask& silhouette);
  // The nearest edge to x (pixels, pixel centres at integers) on row y of
  // the kind a run's left end (`right` false: background, then person) or
  // right end faces, at most `window` pixels away: its position, on the
  // boundary between the two pixels. NaN when there is none.
  float nearest(int y, float x, bool right, int window) const;

 private:
  BitMask rising_;   // bit p: pixel p is person, p − 1 background
  BitMask falling_;  // bit p: pixel p is person, p + 1 background
};

}  // namespace spinewatch::cvsm_detail
