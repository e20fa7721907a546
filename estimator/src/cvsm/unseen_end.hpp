#pragma once
// Whether a view shows where the person ends below (docs/cvsm.md, "A black
// chair"). A dark seat behind a worker in dark clothes cannot be told from
// the person: the silhouette loses the buttocks and the thighs' underside
// on it, its lower outline ends on pixels the view cannot tell from the
// background (SilhouetteResult::unseen) instead of on a straight occluder
// edge (occluder_edge.hpp), and the view shows where the pelvis rests no
// more than a desk's edge would.
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// The share of the silhouette's columns whose lowest pixel has an unseen
// pixel within kUnseenEndGapPx below it. 0 for an empty silhouette or an
// unseen mask of another size.
double share_ending_on_unseen(const BitMask& silhouette, const BitMask& unseen);

// Where dark clothes meet a dark seat the silhouette's lower outline is
// ragged: pixels of the trousers that pass the threshold, then rows of
// neither (their difference between the two thresholds) before the
// unseen ones. Within 8 rows the seat's building medians (the varied
// phantom's black chair, seen from the side) were 0.47–0.75 against
// 0.31–0.64 within 2, while a person with no chair stayed at 0.11–0.24.
inline constexpr int kUnseenEndGapPx = 8;

}  // namespace spinewatch::cvsm_detail
