// The fitted head against a view whose silhouette shows the person's head
// inside the picture (estimator/src/cvsm/head_in_view.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "cvsm/head_in_view.hpp"
#include "cvsm/pelvis_in_view.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

using cvsm_detail::head_beyond_empty_edge;
using cvsm_detail::kHeadBeyondEdgePx;
using cvsm_detail::model_head_centre;

// The topmost row of a silhouette, or -1 when it is empty.
int top_row(const BitMask& m) {
  for (int y = 0; y < m.height(); ++y)
    if (m.count_row(y) > 0) return y;
  return -1;
}

// The bottom row of a silhouette, or -1 when it is empty.
int bottom_row(const BitMask& m) {
  for (int y = m.height(); y-- > 0;)
    if (m.count_row(y) > 0) return y;
  return -1;
}

TEST(HeadInView, TheModelsHeadCentreIsInTheMiddleOfItsDrawnHead) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  for (const CvsmPose& pose : {CvsmPose{}, bend(30, 0, 0), bend(0, 20, 10)}) {
    const SpinePose vertebrae = pose_vertebrae(model, generic_spine_spec(), pose);
    const Eigen::Vector3d head = model_head_centre(model, vertebrae, pose.limbs, pose.heading);
    // Above T1 by the neck and half the head (0.06–0.12 of the stature).
    const double above_t1 = (head - vertebrae[kNeckIndex].body_center).norm();
    EXPECT_GT(above_t1, 0.06 * model.shape.height_mm);
    EXPECT_LT(above_t1, 0.12 * model.shape.height_mm);
    const Views views = render(rig, model, pose);
    for (const auto& [camera, silhouette] : {std::pair{&rig.frontal, &views.frontal}, {&rig.lateral, &views.lateral}}) {
      const std::optional<Eigen::Vector2d> pixel = camera->project(head);
      ASSERT_TRUE(pixel);
      EXPECT_TRUE(silhouette->get(static_cast<int>(std::lround(pixel->x())), static_cast<int>(std::lround(pixel->y()))));
      if (pose.flexion == 0) {
        // Upright: half a head below the drawn head's top, about 7 % of
        // the standing body's drawn height.
        const int top = top_row(*silhouette), tall = bottom_row(*silhouette) - top;
        EXPECT_GT(pixel->y(), top + 0.04 * tall);
        EXPECT_LT(pixel->y(), top + 0.10 * tall);
      }
      EXPECT_FALSE(head_beyond_empty_edge(*camera, *silhouette, head));
    }
  }
}

TEST(HeadInView, BeyondOnlyWhereTheSilhouetteLeavesThatEdgeEmpty) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views views = render(rig, model, CvsmPose{});
  const Eigen::Vector3d head = model_head_centre(model, pose_vertebrae(model, generic_spine_spec(), CvsmPose{}), {}, 0);
  for (const auto& [camera, silhouette] : {std::pair{&rig.frontal, &views.frontal}, {&rig.lateral, &views.lateral}}) {
    ASSERT_GT(top_row(*silhouette), 0);  // the person's crown is in the picture
    // The same person's silhouette running into the top edge (cut there).
    BitMask cut = *silhouette;
    const int top = top_row(cut);
    const int x0 = [&] {
      for (int x = 0; x < kW; ++x)
        if (cut.get(x, top)) return x;
      return 0;
    }();
    for (int y = 0; y < top; ++y) cut.set_span(y, x0, x0 + cvsm_detail::kPelvisCutMinPx + 4);
    // A speck of noise on the top row does not make the edge reached ...
    BitMask speck = *silhouette;
    speck.set_span(0, 10, 10 + cvsm_detail::kPelvisCutMinPx - 2);
    // ... and a head cut by the edge whose outermost row was lost still does.
    BitMask lost_row = cut;
    for (int x = 0; x < kW; ++x) lost_row.set(x, 0, false);
    int beyond = 0, within = 0;
    for (double up = 0; up <= 1500; up += 25) {
      const Eigen::Vector3d raised = head + Eigen::Vector3d(0, up, 0);
      const std::optional<Eigen::Vector2d> pixel = camera->project(raised);
      ASSERT_TRUE(pixel);
      const bool far_above = -pixel->y() > kHeadBeyondEdgePx;
      (far_above ? beyond : within) += 1;
      EXPECT_EQ(head_beyond_empty_edge(*camera, *silhouette, raised), far_above) << up << " mm up";
      EXPECT_EQ(head_beyond_empty_edge(*camera, speck, raised), far_above) << up << " mm up";
      EXPECT_FALSE(head_beyond_empty_edge(*camera, cut, raised)) << up << " mm up";
      EXPECT_FALSE(head_beyond_empty_edge(*camera, lost_row, raised)) << up << " mm up";
    }
    EXPECT_GT(beyond, 3);
    EXPECT_GT(within, 3);
    EXPECT_FALSE(head_beyond_empty_edge(*camera, BitMask{}, head + Eigen::Vector3d(0, 1500, 0)));
  }
}

// Any edge: a camera on its side has the head towards its left or right.
TEST(HeadInView, AnyEdgeOfTheImage) {
  const CameraRig rig = CameraRig::default_rig();
  BitMask body(kW, kH);
  for (int y = 60; y < 180; ++y) body.set_span(y, 100, 220);
  const Eigen::Vector3d centre(0, 900, 0);
  const Eigen::Vector2d at = *rig.frontal.project(centre);
  for (const Eigen::Vector3d& away : {Eigen::Vector3d(0, 0, 3000), Eigen::Vector3d(0, 0, -3000),
                                      Eigen::Vector3d(0, -3000, 0)}) {
    const Eigen::Vector2d pixel = *rig.frontal.project(centre + away);
    ASSERT_GT((pixel - at).norm(), 200);  // far off the image
    EXPECT_TRUE(head_beyond_empty_edge(rig.frontal, body, centre + away));
  }
  EXPECT_FALSE(head_beyond_empty_edge(rig.frontal, body, centre));
}

}  // namespace
}  // namespace spinewatch
