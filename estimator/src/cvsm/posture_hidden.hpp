#pragma once
// What the occluder hides while standing or seated is chosen
// (choose_posture, docs/cvsm.md "Occluded lower body", "Seated or
// standing") and while front is weighed against back (facing_check.hpp,
// docs/cvsm.md "Turned away from the range"). The two models differ below
// the occluder's edge: the seated thighs come towards the camera and spread
// wider than the standing legs, and face one way or the other.
// The fit hides only the straight run's columns (occluder_edge.hpp); there
// the tallest test subject's seated thighs, drawn under his forearms that
// rest on the desk beside the run, were charged where the desk hides them,
// and a standing model squeezed to his seated crown won. For the choice,
// every column the edge's line cuts the person on is hidden.
#include <array>

#include "cvsm/xor_cost.hpp"

namespace spinewatch::cvsm_detail {

// While it lives, `cost` hides, in each view where it hid something, all
// that the occluder's edge cuts (HiddenSpan::Cut) beside what it hid
// (the unseen pixels too); then what it hid before.
class CutSpanHidden {
 public:
  explicit CutSpanHidden(XorCost& cost);
  ~CutSpanHidden();
  CutSpanHidden(const CutSpanHidden&) = delete;
  CutSpanHidden& operator=(const CutSpanHidden&) = delete;

 private:
  XorCost& cost_;
  std::array<const BitMask*, 2> before_{};
  std::array<BitMask, 2> masks_;
};

}  // namespace spinewatch::cvsm_detail
