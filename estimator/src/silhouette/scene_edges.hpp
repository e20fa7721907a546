#pragma once
// Where the person's silhouette ends on the outline of something in the
// scene rather than on a plain stretch of it (docs/cvsm.md, "A desk's
// side"). The stored background holds a desk, a cabinet, a chair; where
// the person sits behind one of them, the silhouette's outline runs along
// the thing's own edge, which the background shows as a step of luma. On
// a wall the outline crosses no such step. The fit reads the occluder's
// side from these pixels (cvsm/side_cut.hpp).
#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::silhouette_detail {

// The background's luma gradient (3×3 Sobel magnitude) that is a thing's
// edge, not the wall's texture or the sensor's noise: a step of 15 grey
// levels gives 60. On the phantom's walls 95 % of the pixels stay under
// 17; the edge of its desk against the wall measures 170–200.
inline constexpr int kSceneEdgeGradient = 60;

// The person's outline pixels (set, with one of the four neighbours
// unset) where the background's gradient is at least `min_gradient`,
// in `out` (resized to the person's size). Pixels on the image's border
// are never marked: the gradient needs all eight neighbours.
void mark_scene_edges(const BitMask& person, const BackgroundModel& background, int min_gradient, BitMask& out);

}  // namespace spinewatch::silhouette_detail
