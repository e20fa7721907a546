#include "cvsm/upright_view.hpp"

#include <algorithm>
#include <cmath>

namespace spinewatch::cvsm_detail {

double image_roll(const CameraModel& camera) {
  // The world's up in camera coordinates; its image direction at the
  // principal point is (x, y) of it (image y points down).
  const Eigen::Vector3d up = camera.R * Eigen::Vector3d::UnitY();
  if (std::hypot(up.x(), up.y()) < 1e-9) return 0;
  // Up on the image is (0, −1): the angle from it to (up.x, up.y).
  return std::atan2(up.x(), -up.y());
}

UprightView::UprightView(const CameraModel& camera, const BitMask& mask) : source_(&mask) {
  roll_ = image_roll(camera);
  level_ = std::abs(roll_) < kLevelRad || mask.empty();
  if (level_) return;
  centre_ = {camera.camera_matrix(0, 2), camera.camera_matrix(1, 2)};
  // A canvas that holds the image turned any way about the principal
  // point: twice the farthest corner's distance from it, square.
  double reach = 0;
  for (const double x : {0.0, static_cast<double>(mask.width())})
    for (const double y : {0.0, static_cast<double>(mask.height())})
      reach = std::max(reach, (Eigen::Vector2d(x, y) - centre_).norm());
  const int side = 2 * static_cast<int>(std::ceil(reach)) + 2;
  offset_ = Eigen::Vector2d(side / 2.0, side / 2.0);
  turned_ = BitMask(side, side);
  border_ = BitMask(side, side);
  // Each canvas pixel takes the image pixel it falls on (nearest).
  const int last_x = mask.width() - 1, last_y = mask.height() - 1;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const Eigen::Vector2d p = to_image({x, y});
      const long ix = std::lround(p.x()), iy = std::lround(p.y());
      if (ix < 0 || iy < 0 || ix > last_x || iy > last_y) continue;
      const int sx = static_cast<int>(ix), sy = static_cast<int>(iy);
      if (!mask.get(sx, sy)) continue;
      turned_.set(x, y);
      if (sx == 0 || sy == 0 || sx == last_x || sy == last_y) border_.set(x, y);
    }
}

bool UprightView::on_image_border(int x, int y) const {
  if (level_) return x == 0 || y == 0 || x == source_->width() - 1 || y == source_->height() - 1;
  return border_.get(x, y);
}

Eigen::Vector2d UprightView::to_image(const Eigen::Vector2d& upright) const {
  if (level_) return upright;
  // The canvas is the image turned by −roll (the world's up to the
  // canvas's up); back to the image: turned by +roll.
  const double c = std::cos(roll_), s = std::sin(roll_);
  const Eigen::Vector2d d = upright - offset_;
  return centre_ + Eigen::Vector2d(c * d.x() - s * d.y(), s * d.x() + c * d.y());
}

}  // namespace spinewatch::cvsm_detail
