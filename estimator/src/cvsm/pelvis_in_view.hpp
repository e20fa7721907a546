#pragma once
// Whether a view shows the subject's pelvis (docs/cvsm.md, "Pelvis out of
// the picture"). A worker seated close to a camera fills its picture from
// the head down and the image ends at his chest: his silhouette runs into
// the image's bottom edge, and below it the view says nothing. The waist
// (L5) is placed by the pelvis's outline and the legs' direction; where
// neither view shows them, the fit puts the waist where the model's
// proportions carry it from the shoulders, and on the shared real footage's
// own geometry that was 84–105 mm off the truth on every pair while the cost
// said the fit stood. A head or feet cut by the image are no such case: the
// pelvis is in view above them.
#include <optional>

#include <Eigen/Core>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// The image edges, in the order edge_beyond() tells them.
enum class ImageEdge { Bottom, Top, Left, Right };

// The edge of a width × height image a pixel lies beyond (the one it is
// farthest beyond), nothing when it is inside.
std::optional<ImageEdge> edge_beyond(const Eigen::Vector2d& pixel, int width, int height);

// The edge a pixel is farthest beyond (or nearest inside) and by how much:
// positive beyond it, negative or zero inside the image.
struct EdgeDistance {
  ImageEdge edge = ImageEdge::Bottom;
  double beyond_px = 0;
};
EdgeDistance farthest_edge(const Eigen::Vector2d& pixel, int width, int height);

// Silhouette pixels on one edge of the image: the bottom or top row, the
// left or right column.
int pixels_on_edge(const BitMask& silhouette, ImageEdge edge);

// The view does not show the pelvis: both hip joints of the model at
// `vertebrae` (its fitted spine) project outside the image, and the
// silhouette runs into the edge they lie beyond on at least
// kPelvisCutMinPx pixels. Any edge, not only the bottom: a camera on its
// side has the body's feet towards its left or right edge.
bool pelvis_out_of_view(const CameraModel& camera, const BitMask& silhouette, const BodyModel& model,
                        const SpinePose& vertebrae);

// The silhouette on that edge that counts as cut there, not a stray pixel
// of noise.
inline constexpr int kPelvisCutMinPx = 8;

}  // namespace spinewatch::cvsm_detail
