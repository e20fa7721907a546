#pragma once
// The image region of a standing subject's legs, for the step search
// (docs/cvsm.md, "A step aside"). The CVSM template holds the legs straight
// and together; a worker stepping aside spreads them, and the whole-outline
// XOR then keeps the model's pelvis over the leg that stood still and bends
// the trunk over to reach the shoulders (stride: a 39° side bend, the waist
// 110 mm off). Where the legs are not counted, the trunk and pelvis are
// placed by their own outline.
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// Sets `out` (width × height) to every pixel on the rows at and below the
// higher of the model's two hip joints as `camera` sees them (the model at
// `vertebrae`), plus the pixels of `also` (an occluder's hidden region, or
// null). Only meaningful for an upright trunk: bent forward in a view that
// looks down on it, the trunk itself projects below the hips.
void hide_below_hips(const CameraModel& camera, const BodyModel& model, const SpinePose& vertebrae,
                     const BitMask* also, int width, int height, BitMask& out);

}  // namespace spinewatch::cvsm_detail
