#include "cvsm/head_in_view.hpp"

#include <algorithm>
#include <vector>

#include "cvsm/pelvis_in_view.hpp"

namespace spinewatch::cvsm_detail {
namespace {

// The most silhouette pixels on any row (or column) within `band` of an edge.
int most_near_edge(const BitMask& silhouette, ImageEdge edge, int band) {
  const int w = silhouette.width(), h = silhouette.height();
  int most = 0;
  for (int i = 0; i < band; ++i) {
    int n = 0;
    if (edge == ImageEdge::Top || edge == ImageEdge::Bottom) {
      if (i >= h) break;
      n = static_cast<int>(silhouette.count_row(edge == ImageEdge::Top ? i : h - 1 - i));
    } else {
      if (i >= w) break;
      const int x = edge == ImageEdge::Left ? i : w - 1 - i;
      for (int y = 0; y < h; ++y) n += silhouette.get(x, y) ? 1 : 0;
    }
    most = std::max(most, n);
  }
  return most;
}

}  // namespace

Eigen::Vector3d model_head_centre(const BodyModel& model, const SpinePose& vertebrae, const LimbPose& limbs,
                                  double heading_deg) {
  // The head's planes are the ones the neck turns (body_model.cpp).
  int widest = -1;
  for (std::size_t p = 0; p < model.planes.size(); ++p)
    if (model.planes[p].joint == static_cast<int>(JointId::Neck) &&
        (widest < 0 || model.planes[p].half_width > model.planes[static_cast<std::size_t>(widest)].half_width))
      widest = static_cast<int>(p);
  if (widest < 0) return vertebrae[kNeckIndex].body_center;
  std::vector<Eigen::Vector3d> points;
  control_points(model, vertebrae, points, limbs, heading_deg);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int k = 0; k < kControlPoints; ++k) centre += points[static_cast<std::size_t>(widest * kControlPoints + k)];
  return centre / kControlPoints;
}

bool head_beyond_empty_edge(const CameraModel& camera, const BitMask& silhouette, const Eigen::Vector3d& head_centre) {
  if (silhouette.empty()) return false;
  const std::optional<Eigen::Vector2d> pixel = camera.project(head_centre);
  if (!pixel) return false;
  const EdgeDistance beyond = farthest_edge(*pixel, silhouette.width(), silhouette.height());
  return beyond.beyond_px > kHeadBeyondEdgePx && most_near_edge(silhouette, beyond.edge, kEdgeBandPx) < kPelvisCutMinPx;
}

}  // namespace spinewatch::cvsm_detail
