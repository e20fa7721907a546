#include "cvsm/fixed_camera.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch {

FixedCamera::FixedCamera(const CameraModel& camera) : camera_(camera) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r_[i][j] = std::llround(camera.R(i, j) * (1 << 20));
    t_[i] = std::llround(camera.t(i) * (1 << 24));
  }
  distorted_ = camera.has_distortion();
  fx_ = std::llround(camera.camera_matrix(0, 0) * 256);
  fy_ = std::llround(camera.camera_matrix(1, 1) * 256);
  cx_ = std::llround(camera.camera_matrix(0, 2) * 256);
  cy_ = std::llround(camera.camera_matrix(1, 2) * 256);
}

bool FixedCamera::project(const Eigen::Vector3d& world, PixelQ8& out) const {
  if (distorted_) {
    const auto p = camera_.project(world);
    if (!p) return false;
    const double limit = kQ8Limit;
    out.u = static_cast<std::int32_t>(std::lround(std::clamp(p->x() * 256, -limit, limit)));
    out.v = static_cast<std::int32_t>(std::lround(std::clamp(p->y() * 256, -limit, limit)));
    return true;
  }
  // Round to nearest (std::llround is a library call; this is the hot loop).
  auto q4 = [](double v) { return static_cast<std::int64_t>(v * 16 + (v >= 0 ? 0.5 : -0.5)); };
  const std::int64_t x = q4(world.x()), y = q4(world.y()), z = q4(world.z());
  std::int64_t c[3];
  for (int i = 0; i < 3; ++i) c[i] = r_[i][0] * x + r_[i][1] * y + r_[i][2] * z + t_[i];  // Q24
  if (c[2] < (std::int64_t{1} << 24)) return false;
  out.u = static_cast<std::int32_t>(std::clamp<std::int64_t>(cx_ + fx_ * c[0] / c[2], -kQ8Limit, kQ8Limit));
  out.v = static_cast<std::int32_t>(std::clamp<std::int64_t>(cy_ + fy_ * c[1] / c[2], -kQ8Limit, kQ8Limit));
  return true;
}

}  // namespace spinewatch
