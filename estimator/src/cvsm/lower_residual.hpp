#pragma once
// What a fit leaves unexplained below the waist (docs/cvsm.md, "Arms where
// the views show them"). The auto limbs search only the arms: a pair whose
// fixed fit is off because the legs stepped or bent (a lunge, a stride) is
// not one the arms can put right, though moving them and the trunk lowers
// the cost; there the posture stays the fixed fit's.
#include <cstdint>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// Pixels on rows first_row … the last where `model` and `silhouette` differ,
// not counting those `hidden` holds (nullptr: none). The masks are of one
// size; first_row may lie outside the image.
std::int64_t xor_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden, int first_row);

// Of those, the silhouette's pixels the model does not draw: what the
// person shows there and the fit leaves out (a leg stepped out of the
// held-straight legs' outline), not what the model draws that the person
// does not show (the hanging arms of a fit whose arms are raised).
std::int64_t silhouette_outside_below(const BitMask& model, const BitMask& silhouette, const BitMask* hidden,
                                      int first_row);

}  // namespace spinewatch::cvsm_detail
