#pragma once
// What the CVSM tests fit to: a subject unlike the generic model, its
// silhouettes drawn by the OpenCV reference renderer, and bends.
#include <vector>

#include "cvsm_reference.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch {

inline constexpr int kW = 320, kH = 240;

// A subject unlike the generic model: shorter, slimmer, off the axis.
inline BodyModel other_subject(SubjectPosture posture = SubjectPosture::Standing) {
  BodyShape shape;
  shape.height_mm = 1620;
  shape.width_scale = 0.9;
  shape.depth_scale = 0.93;
  shape.shoulder_scale = 0.95;
  shape.limb_scale = 0.9;
  shape.posture = posture;
  const double l5_y = posture == SubjectPosture::Standing ? generic_spine_spec().l5_height_fraction * 1620 : 560;
  return build_body_model(generic_cvsm_spec(), generic_spine_spec(), shape, {20, l5_y, -15});
}

struct Views {
  BitMask frontal, lateral;
};

inline Views render(const CameraRig& rig, const BodyModel& model, const CvsmPose& pose) {
  std::vector<Eigen::Vector3d> pts;
  control_points(model, pose_vertebrae(model, generic_spine_spec(), pose), pts, pose.limbs);
  cv::Mat f(kH, kW, CV_8U), l(kH, kW, CV_8U);
  test::render_reference(rig.frontal, model, pts, f);
  test::render_reference(rig.lateral, model, pts, l);
  return {test::to_mask(f), test::to_mask(l)};
}

inline CvsmPose bend(double flexion, double lateral, double twist) {
  CvsmPose p;
  p.flexion = flexion * 2 / 3;
  p.pelvis_flexion = flexion / 3;
  p.lateral = lateral;
  p.twist = twist;
  return p;
}

}  // namespace spinewatch
