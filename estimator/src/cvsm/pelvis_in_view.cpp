#include "cvsm/pelvis_in_view.hpp"

#include "spinewatch/estimator/vertebra_levels.hpp"

namespace spinewatch::cvsm_detail {

int pixels_on_edge(const BitMask& silhouette, ImageEdge edge) {
  const int w = silhouette.width(), h = silhouette.height();
  if (edge == ImageEdge::Bottom || edge == ImageEdge::Top)
    return static_cast<int>(silhouette.count_row(edge == ImageEdge::Bottom ? h - 1 : 0));
  const int x = edge == ImageEdge::Right ? w - 1 : 0;
  int n = 0;
  for (int y = 0; y < h; ++y) n += silhouette.get(x, y) ? 1 : 0;
  return n;
}

std::optional<ImageEdge> edge_beyond(const Eigen::Vector2d& pixel, int width, int height) {
  const EdgeDistance farthest = farthest_edge(pixel, width, height);
  if (farthest.beyond_px <= 0) return std::nullopt;
  return farthest.edge;
}

EdgeDistance farthest_edge(const Eigen::Vector2d& pixel, int width, int height) {
  const double beyond[4] = {pixel.y() - (height - 1), -pixel.y(), -pixel.x(), pixel.x() - (width - 1)};
  int best = 0;
  for (int e = 1; e < 4; ++e)
    if (beyond[e] > beyond[best]) best = e;
  return {static_cast<ImageEdge>(best), beyond[best]};
}

bool pelvis_out_of_view(const CameraModel& camera, const BitMask& silhouette, const BodyModel& model,
                        const SpinePose& vertebrae) {
  if (silhouette.empty()) return false;
  // The hip joints as the model places them on its L5 (body_model.cpp's
  // leg frames).
  const Eigen::Matrix3d waist = vertebrae[kWaistIndex].q.toRotationMatrix();
  Eigen::Vector2d mid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& hip : {model.hip_left, model.hip_right}) {
    const std::optional<Eigen::Vector2d> pixel = camera.project(vertebrae[kWaistIndex].body_center + waist * hip);
    if (!pixel || !edge_beyond(*pixel, silhouette.width(), silhouette.height())) return false;
    mid += 0.5 * *pixel;
  }
  // The body runs out of the picture towards them: cut by that edge.
  const std::optional<ImageEdge> edge = edge_beyond(mid, silhouette.width(), silhouette.height());
  return edge && pixels_on_edge(silhouette, *edge) >= kPelvisCutMinPx;
}

}  // namespace spinewatch::cvsm_detail
