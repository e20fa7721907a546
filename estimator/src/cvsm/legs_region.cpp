#include "cvsm/legs_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "spinewatch/estimator/vertebra_levels.hpp"

namespace spinewatch::cvsm_detail {

void hide_below_hips(const CameraModel& camera, const BodyModel& model, const SpinePose& vertebrae,
                     const BitMask* also, int width, int height, BitMask& out) {
  if (also)
    out = *also;
  else if (out.width() != width || out.height() != height)
    out = BitMask(width, height);
  else
    out.clear();
  // The hip joints as the model places them on its L5 (body_model.cpp's leg
  // frames); the higher one in the image, so no pelvis row is hidden.
  const Eigen::Matrix3d waist = vertebrae[kWaistIndex].q.toRotationMatrix();
  double top = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& hip : {model.hip_left, model.hip_right})
    if (const auto pixel = camera.project(vertebrae[kWaistIndex].body_center + waist * hip)) top = std::min(top, pixel->y());
  if (!std::isfinite(top)) return;
  for (int y = std::max(0, static_cast<int>(std::ceil(top))); y < height; ++y) out.set_span(y, 0, width - 1);
}

}  // namespace spinewatch::cvsm_detail
