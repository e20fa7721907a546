#include "spinewatch/estimator/camera_model.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace spinewatch {

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d c = to_camera(world);
  if (c.z() <= 1e-6) return std::nullopt;
  double x = c.x() / c.z();
  double y = c.y() / c.z();
  if (has_distortion()) {
    const auto [k1, k2, p1, p2, k3] = dist_coeffs;
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    x = xd;
    y = yd;
  }
  const auto& K = camera_matrix;
  // Skew (K(0,1)) is ignored, as cv::projectPoints ignores it.
  return Eigen::Vector2d(K(0, 0) * x + K(0, 2), K(1, 1) * y + K(1, 2));
}

Eigen::Vector3d CameraModel::ray_through(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector3d h(pixel.x(), pixel.y(), 1.0);
  const Eigen::Vector3d cam = camera_matrix.inverse() * h;
  return (R.transpose() * cam).normalized();
}

bool CameraModel::has_distortion() const {
  for (double d : dist_coeffs)
    if (d != 0.0) return true;
  return false;
}

CameraRig CameraRig::default_rig() {
  Eigen::Matrix3d K;
  K << 300, 0, 160, 0, 300, 120, 0, 0, 1;
  CameraRig rig;
  // Frontal: at (2000, 1100, 0), optical axis −X; image right is the
  // subject's left (−Z), image down is −Y.
  rig.frontal.camera_matrix = K;
  rig.frontal.R << 0, 0, -1, 0, -1, 0, -1, 0, 0;
  rig.frontal.t = -rig.frontal.R * Eigen::Vector3d(2000, 1100, 0);
  // Lateral: at (0, 1100, 2000), optical axis −Z; image right is anterior (+X).
  rig.lateral.camera_matrix = K;
  rig.lateral.R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  rig.lateral.t = -rig.lateral.R * Eigen::Vector3d(0, 1100, 2000);
  return rig;
}

}  // namespace spinewatch
