// The pose's heading (body_model.hpp, CvsmPose::heading): the whole body,
// legs included, turned about the vertical through the hip joints, against
// the reference (the unturned pose's points turned by hand).
#include <gtest/gtest.h>

#include "cvsm/subject_heading.hpp"
#include "cvsm/xor_cost.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

TEST(CvsmHeadingModel, TurnedPoseIsTheUnturnedOneTurnedAboutTheHips) {
  const BodyModel model = other_subject();
  CvsmPose pose = bend(20, 5, 3);
  pose.translation = {12, -4, -7};
  pose.limbs.side[0].hip_flexion = 25;
  pose.limbs.side[1].knee = 30;
  pose.limbs.side[1].shoulder_abduction = 40;
  for (const double heading : {90.0, 137.0, 180.0, -60.0}) {
    CvsmPose turned = pose;
    turned.heading = heading;
    const SpinePose v0 = pose_vertebrae(model, generic_spine_spec(), pose);
    const SpinePose v1 = pose_vertebrae(model, generic_spine_spec(), turned);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(heading * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d pivot =
        model.neutral[kWaistIndex].body_center + 0.5 * (model.hip_left + model.hip_right) + pose.translation;
    for (std::size_t k = 0; k < kVertebraCount; ++k) {
      EXPECT_LT((v1[k].body_center - (pivot + R * (v0[k].body_center - pivot))).norm(), 1e-9) << heading << " " << k;
      EXPECT_LT((v1[k].q.toRotationMatrix() - R * v0[k].q.toRotationMatrix()).norm(), 1e-9) << heading << " " << k;
    }
    std::vector<Eigen::Vector3d> p0, p1;
    control_points(model, v0, p0, pose.limbs);
    control_points(model, v1, p1, turned.limbs, turned.heading);
    ASSERT_EQ(p0.size(), p1.size());
    for (std::size_t i = 0; i < p0.size(); ++i) {
      if (!model.in_chain[i / kControlPoints]) continue;
      EXPECT_LT((p1[i] - (pivot + R * (p0[i] - pivot))).norm(), 1e-9) << heading << " point " << i;
    }
  }
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

// Silhouettes drawn from `poses` together (their union).
Views render_union(const CameraRig& rig, const BodyModel& model, std::initializer_list<CvsmPose> poses) {
  cv::Mat f = cv::Mat::zeros(kH, kW, CV_8U), l = cv::Mat::zeros(kH, kW, CV_8U);
  for (const CvsmPose& pose : poses) {
    std::vector<Eigen::Vector3d> pts;
    control_points(model, pose_vertebrae(model, generic_spine_spec(), pose), pts, pose.limbs, pose.heading);
    cv::Mat one_f(kH, kW, CV_8U), one_l(kH, kW, CV_8U);
    test::render_reference(rig.frontal, model, pts, one_f);
    test::render_reference(rig.lateral, model, pts, one_l);
    cv::max(f, one_f, f);
    cv::max(l, one_l, l);
  }
  return {test::to_mask(f), test::to_mask(l)};
}

cvsm_detail::HeadingChoice choose_on(const Views& v, double& heading) {
  const CameraRig rig = CameraRig::default_rig();
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(v.frontal, v.lateral);
  CvsmOptions options;
  options.heading = HeadingRange::Any;
  cvsm_detail::SubjectEstimate s =
      cvsm_detail::initial_subject(rig, generic_cvsm_spec(), generic_spine_spec(), options, v.frontal, v.lateral);
  const cvsm_detail::HeadingChoice choice = cvsm_detail::choose_heading(s, cost, generic_cvsm_spec(), generic_spine_spec(), options);
  heading = s.pose.heading;
  return choice;
}

TEST(CvsmHeadingChoice, FindsTheHeadingAndSaysWhenFrontAndBackCostTheSame) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  for (const double truth : {0.0, 90.0, 180.0, -120.0}) {
    CvsmPose pose;
    pose.heading = truth;
    double found = 0;
    const cvsm_detail::HeadingChoice choice = choose_on(render_union(rig, model, {pose}), found);
    EXPECT_TRUE(choice.resolved()) << truth << ": margin " << choice.margin_px << " of " << choice.silhouette_px;
    EXPECT_LE(cvsm_detail::heading_apart(found, truth), 10) << truth << ": found " << found;
  }
  // The body and its turn by 180° about the hips drawn together: whatever
  // faces one way has a twin facing the other, so front and back cost
  // about the same and the choice must say it cannot tell. (With the
  // generic spine placement, as here: with the measured one the model's
  // front/back asymmetry under perspective made one side 2.2 % better,
  // beyond the margin — docs/cvsm.md, "Heading", limits.)
  CvsmPose front, back;
  back.heading = 180;
  double found = 0;
  const cvsm_detail::HeadingChoice twin = choose_on(render_union(rig, model, {front, back}), found);
  EXPECT_FALSE(twin.resolved()) << "margin " << twin.margin_px << " of " << twin.silhouette_px;
}

// The tracker on those twin silhouettes: its subject model never
// completes, so nothing is published as tracking.
TEST(CvsmHeadingChoice, UndecidedHeadingIsNeverTracking) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  CvsmOptions options;
  options.heading = HeadingRange::Any;  // the twins are front and back
  options.subject_frames = 3;
  options.spine_placement = SpinePlacementMode::Generic;  // as the choice above
  CvsmTracker tracker(rig, options);
  CvsmPose front, back;
  back.heading = 180;
  const Views twin = render_union(rig, model, {front, back});
  int init = 0;
  for (int i = 0; i < 8; ++i) {
    const CvsmResult r = tracker.track(twin.frontal, twin.lateral);
    EXPECT_NE(r.state, TrackingState::Tracking) << "pair " << i;
    init += r.state == TrackingState::Init;
  }
  EXPECT_EQ(init, 8);
  // The same body alone is tracked once its model is complete.
  CvsmTracker alone(rig, options);
  const Views one = render_union(rig, model, {front});
  CvsmResult last;
  for (int i = 0; i < 4; ++i) last = alone.track(one.frontal, one.lateral);
  EXPECT_EQ(last.state, TrackingState::Tracking);
}

}  // namespace
}  // namespace spinewatch
