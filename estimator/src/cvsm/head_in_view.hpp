#pragma once
// Whether the fitted head lies where the person's head is (docs/cvsm.md,
// "Head above the picture"). The cost counts only pixels inside the image:
// a model placed too high pays nothing for a head that leaves the picture,
// and its neck and shoulders then take the place of the person's head. On
// the shared real footage (BlazePose masks, cam_1/cam_2) that fit stood at a
// cost of 0.19 and drew the 17 vertebrae from the man's crown to his chin.
// A head that the image cuts runs into the edge; where the silhouette leaves
// that edge empty, the fitted head's middle cannot be beyond it.
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// The middle of the model's head at `vertebrae`, `limbs` and `heading_deg`:
// the centre of its widest control plane (world, mm).
Eigen::Vector3d model_head_centre(const BodyModel& model, const SpinePose& vertebrae, const LimbPose& limbs,
                                  double heading_deg);

// The view contradicts the fitted head: its middle projects more than
// kHeadBeyondEdgePx beyond an edge of the image, and no row (or column) of
// the silhouette within kEdgeBandPx of that edge holds kPelvisCutMinPx
// pixels — the person's head ends inside the picture.
bool head_beyond_empty_edge(const CameraModel& camera, const BitMask& silhouette, const Eigen::Vector3d& head_centre);

// Half the head may leave the picture with its top (a tall worker close to
// the camera); beyond that margin more than half of it has. Pixels at the
// camera's size.
inline constexpr double kHeadBeyondEdgePx = 12;
// A silhouette whose outermost rows were lost (a drifting light takes the
// head's top row or two) still reaches the edge.
inline constexpr int kEdgeBandPx = 2;

}  // namespace spinewatch::cvsm_detail
