#include "pelvis_in_view.hpp"

#include "spinewatch/estimator/vertebra_levels.hpp"

namespace spinewatch::cvsm_detail {

bool pelvis_below_view(const CameraModel& camera, const BitMask& silhouette, const BodyModel& model,
                       const SpinePose& vertebrae) {
  if (silhouette.empty()) return false;
  const int bottom = silhouette.height() - 1;
  if (silhouette.count_row(bottom) < kPelvisCutMinPx) return false;
  // The hip joints as the model places them on its L5 (body_model.cpp's
  // leg frames), in the image's rows.
  const Eigen::Matrix3d waist = vertebrae[kWaistIndex].q.toRotationMatrix();
  for (const Eigen::Vector3d& hip : {model.hip_left, model.hip_right}) {
    const std::optional<Eigen::Vector2d> pixel = camera.project(vertebrae[kWaistIndex].body_center + waist * hip);
    if (!pixel || pixel->y() <= bottom) return false;
  }
  return true;
}

}  // namespace spinewatch::cvsm_detail
