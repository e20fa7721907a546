#include "spinewatch/estimator/camera_model.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace spinewatch {
namespace {

// OpenCV's tilted-sensor matrix (computeTiltProjectionMatrix): the sensor
// rotated by τx about x and τy about y, then projected back onto z = 1.
Eigen::Matrix3d tilt_matrix(double tau_x, double tau_y) {
  const double cx = std::cos(tau_x), sx = std::sin(tau_x), cy = std::cos(tau_y), sy = std::sin(tau_y);
  Eigen::Matrix3d rot_x, rot_y;
  rot_x << 1, 0, 0, 0, cx, sx, 0, -sx, cx;
  rot_y << cy, 0, -sy, 0, 1, 0, sy, 0, cy;
  const Eigen::Matrix3d rot = rot_y * rot_x;
  Eigen::Matrix3d proj_z;
  proj_z << rot(2, 2), 0, -rot(0, 2), 0, rot(2, 2), -rot(1, 2), 0, 0, 1;
  return proj_z * rot;
}

}  // namespace

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& normalised) const {
  const double x = normalised.x(), y = normalised.y();
  const auto& d = dist_coeffs;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
  const double r2 = x * x + y * y;
  double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  // The rational model divides by 1 + k4 r² + k5 r⁴ + k6 r⁶; skipped when
  // those are zero, so the classic five-coefficient arithmetic is exactly
  // what it was before the longer models (and what the fits were tuned on).
  if (d[5] != 0 || d[6] != 0 || d[7] != 0) radial /= 1 + r2 * (d[5] + r2 * (d[6] + r2 * d[7]));
  double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  xd += r2 * (d[8] + r2 * d[9]);    // thin prism s1, s2
  yd += r2 * (d[10] + r2 * d[11]);  // thin prism s3, s4
  if (d[12] != 0 || d[13] != 0) {
    const Eigen::Vector3d tilted = tilt_matrix(d[12], d[13]) * Eigen::Vector3d(xd, yd, 1);
    const double inv = tilted.z() != 0 ? 1 / tilted.z() : 1;
    xd = inv * tilted.x();
    yd = inv * tilted.y();
  }
  return {xd, yd};
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d c = to_camera(world);
  if (c.z() <= 1e-6) return std::nullopt;
  Eigen::Vector2d n(c.x() / c.z(), c.y() / c.z());
  if (has_distortion()) n = distort(n);
  const auto& K = camera_matrix;
  // Skew (K(0,1)) is ignored, as cv::projectPoints ignores it.
  return Eigen::Vector2d(K(0, 0) * n.x() + K(0, 2), K(1, 1) * n.y() + K(1, 2));
}

std::optional<Eigen::Vector2d> CameraModel::normalised(const Eigen::Vector2d& pixel) const {
  const auto& K = camera_matrix;
  const Eigen::Vector2d target((pixel.x() - K(0, 2)) / K(0, 0), (pixel.y() - K(1, 2)) / K(1, 1));
  if (!has_distortion()) return target;
  // Newton's method on distort(n) = target from n = target; the Jacobian by
  // central differences (the model is smooth and cheap). Converges in 3–5
  // steps for real lenses inside their field of view.
  Eigen::Vector2d n = target;
  constexpr double h = 1e-7;
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Vector2d residual = distort(n) - target;
    if (!residual.allFinite()) return std::nullopt;
    if (residual.norm() < 1e-12) return n;
    Eigen::Matrix2d J;
    J.col(0) = (distort(n + Eigen::Vector2d(h, 0)) - distort(n - Eigen::Vector2d(h, 0))) / (2 * h);
    J.col(1) = (distort(n + Eigen::Vector2d(0, h)) - distort(n - Eigen::Vector2d(0, h))) / (2 * h);
    if (std::abs(J.determinant()) < 1e-9) return std::nullopt;  // the model folds over here
    n -= J.inverse() * residual;
  }
  return (distort(n) - target).norm() < 1e-9 ? std::optional<Eigen::Vector2d>(n) : std::nullopt;
}

Eigen::Vector3d CameraModel::ray_through(const Eigen::Vector2d& pixel) const {
  Eigen::Vector3d cam;
  if (const auto n = normalised(pixel)) {
    cam = Eigen::Vector3d(n->x(), n->y(), 1.0);
  } else {
    cam = camera_matrix.inverse() * Eigen::Vector3d(pixel.x(), pixel.y(), 1.0);
  }
  return (R.transpose() * cam).normalized();
}

bool CameraModel::has_distortion() const {
  for (double d : dist_coeffs)
    if (d != 0.0) return true;
  return false;
}

std::vector<double> CameraModel::distortion() const {
  std::size_t used = 0;
  for (std::size_t i = 0; i < kMaxDistortion; ++i)
    if (dist_coeffs[i] != 0.0) used = i + 1;
  std::size_t length = 5;
  for (int l : kDistortionLengths)
    if (static_cast<std::size_t>(l) >= used && static_cast<std::size_t>(l) >= 5) {
      length = static_cast<std::size_t>(l);
      break;
    }
  return {dist_coeffs.begin(), dist_coeffs.begin() + static_cast<std::ptrdiff_t>(length)};
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
