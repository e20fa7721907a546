#pragma once
// What the CVSM tests fit to: a subject unlike the generic model, its
// silhouettes drawn by the OpenCV reference renderer, and bends.
#include <algorithm>
#include <functional>
#include <vector>

#include "cvsm_reference.hpp"
#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
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
  control_points(model, pose_vertebrae(model, generic_spine_spec(), pose), pts, pose.limbs, pose.heading);
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

// Neck and waist errors of a tracker over a rendered sequence: means over
// the tracked pairs, maxima, and how many pairs were lost (init pairs are
// not counted). `each` sees every tracked pair with its truth and errors.
struct SequenceErrors {
  double neck_mean = 0, waist_mean = 0, neck_max = 0, waist_max = 0;
  int lost = 0, frames = 0;
};
using TrackedPair = std::function<void(const CvsmPose& truth, const CvsmResult& result, double neck_mm, double waist_mm)>;

inline SequenceErrors track_sequence(CvsmTracker& tracker, const CameraRig& rig, const BodyModel& subject,
                                     const std::vector<CvsmPose>& poses, const TrackedPair& each = {}) {
  SequenceErrors e;
  for (const CvsmPose& p : poses) {
    const Views v = render(rig, subject, p);
    const CvsmResult r = tracker.track(v.frontal, v.lateral);
    if (r.state == TrackingState::Init) continue;
    ++e.frames;
    if (r.state == TrackingState::Lost) {
      ++e.lost;
      continue;
    }
    const SpinePose truth = pose_vertebrae(subject, generic_spine_spec(), p);
    const double dn = (r.neck - truth[kNeckIndex].body_center).norm();
    const double dw = (r.waist - truth[kWaistIndex].body_center).norm();
    e.neck_mean += dn;
    e.waist_mean += dw;
    e.neck_max = std::max(e.neck_max, dn);
    e.waist_max = std::max(e.waist_max, dw);
    if (each) each(p, r, dn, dw);
  }
  const int ok = std::max(1, e.frames - e.lost);
  e.neck_mean /= ok;
  e.waist_mean /= ok;
  return e;
}

}  // namespace spinewatch
