// The tracker's pure parts (estimator/src/cvsm/): the searches' parameter
// vectors and their way to and from the model's poses (search_params.hpp),
// the armless model the articulated trunk is searched on (armless_model.hpp)
// and the options without the worker's given body (subject_estimate.hpp).
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "cvsm/armless_model.hpp"
#include "cvsm/search_params.hpp"
#include "cvsm/subject_estimate.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch::cvsm_detail {
namespace {

// A bend the search's parameters move along as one: the total flexion,
// a third of it in the pelvis; the residual says only how it is shared.
TEST(CvsmSearchParams, TotalFlexionIsSharedAThirdToThePelvis) {
  const PoseParams a{30, 0, 0, 0, 0, 0, 0, 0};
  const CvsmPose p = to_pose(a, {});
  EXPECT_DOUBLE_EQ(p.pelvis_flexion, 10);
  EXPECT_DOUBLE_EQ(p.flexion, 20);
  // The residual moves the pelvis's share, the total stays.
  const CvsmPose q = to_pose({30, 0, 0, 5, 0, 0, 0, 0}, {});
  EXPECT_DOUBLE_EQ(q.pelvis_flexion, 15);
  EXPECT_DOUBLE_EQ(q.flexion + q.pelvis_flexion, 30);
}

TEST(CvsmSearchParams, TrunkPoseRoundTrips) {
  CvsmPose p;
  p.flexion = 23;
  p.pelvis_flexion = 4;  // not a third of the total: a residual of −5
  p.lateral = -7;
  p.twist = 12;
  p.pelvis_lateral = 3;
  p.translation = {15, -30, 40};
  p.limbs.side[1].elbow = 35;
  const PoseParams a = to_params(p);
  EXPECT_DOUBLE_EQ(a[0], 27);
  EXPECT_DOUBLE_EQ(a[3], -5);
  EXPECT_DOUBLE_EQ(a[1], -7);
  EXPECT_DOUBLE_EQ(a[2], 12);
  EXPECT_DOUBLE_EQ(a[4], 3);
  EXPECT_DOUBLE_EQ(a[5], 15);
  EXPECT_DOUBLE_EQ(a[6], -30);
  EXPECT_DOUBLE_EQ(a[7], 40);
  const CvsmPose back = to_pose(a, p.limbs);
  EXPECT_NEAR(back.flexion, p.flexion, 1e-12);
  EXPECT_NEAR(back.pelvis_flexion, p.pelvis_flexion, 1e-12);
  EXPECT_EQ(back.lateral, p.lateral);
  EXPECT_EQ(back.twist, p.twist);
  EXPECT_EQ(back.pelvis_lateral, p.pelvis_lateral);
  EXPECT_EQ(back.translation, p.translation);
  EXPECT_EQ(back.limbs.side[1].elbow, 35);  // the limbs given are the pose's
  EXPECT_EQ(back.heading, 0);               // the heading is not a trunk parameter
}

// The limbs' order: per side (left, right) shoulder flexion, abduction,
// elbow, hip flexion, abduction, knee; then the head's three.
TEST(CvsmSearchParams, LimbsInTheirOrderAndBack) {
  LimbParams a{};
  for (std::size_t i = 0; i < kLimbParams; ++i) a[i] = static_cast<double>(i + 1);
  const LimbPose l = to_limbs(a);
  EXPECT_EQ(l.side[0].shoulder_flexion, 1);
  EXPECT_EQ(l.side[0].shoulder_abduction, 2);
  EXPECT_EQ(l.side[0].elbow, 3);
  EXPECT_EQ(l.side[0].hip_flexion, 4);
  EXPECT_EQ(l.side[0].hip_abduction, 5);
  EXPECT_EQ(l.side[0].knee, 6);
  EXPECT_EQ(l.side[1].shoulder_flexion, 7);
  EXPECT_EQ(l.side[1].knee, 12);
  EXPECT_EQ(l.head_flexion, 13);
  EXPECT_EQ(l.head_lateral, 14);
  EXPECT_EQ(l.head_turn, 15);
  EXPECT_EQ(to_limb_params(l), a);
}

TEST(CvsmSearchParams, LimbRangeHoldsItsBoundsAndNothingBeyond) {
  EXPECT_TRUE(in_range(LimbParams{}));  // the neutral limbs
  for (std::size_t i = 0; i < kLimbParams; ++i) {
    ASSERT_LT(kLimbRange[i][0], 0) << i;  // every joint can go either way from neutral
    ASSERT_GT(kLimbRange[i][1], 0) << i;
    for (std::size_t end = 0; end < 2; ++end) {
      LimbParams a{};
      a[i] = kLimbRange[i][end];
      EXPECT_TRUE(in_range(a)) << i << " at " << a[i];
      a[i] += end == 0 ? -0.5 : 0.5;
      EXPECT_FALSE(in_range(a)) << i << " at " << a[i];
    }
  }
}

bool arm_joint(int joint) {
  return joint == static_cast<int>(JointId::ShoulderLeft) || joint == static_cast<int>(JointId::ElbowLeft) ||
         joint == static_cast<int>(JointId::ShoulderRight) || joint == static_cast<int>(JointId::ElbowRight);
}

// The arms' two chains leave, every plane of them out of the chains; the
// trunk, legs and head keep theirs, planes and points as built.
TEST(CvsmArmlessModel, DropsTheArmsChainsOnly) {
  const BodyModel model = other_subject();
  const BodyModel armless = without_arms(model);
  ASSERT_EQ(armless.chains.size() + 2, model.chains.size());
  ASSERT_EQ(armless.planes.size(), model.planes.size());
  EXPECT_EQ(armless.local_points, model.local_points);
  int arm_planes = 0, kept_planes = 0;
  for (std::size_t i = 0; i < model.planes.size(); ++i) {
    if (arm_joint(model.planes[i].joint)) {
      ++arm_planes;
      EXPECT_EQ(armless.in_chain[i], 0) << "arm plane " << i;
    } else if (model.in_chain[i]) {
      ++kept_planes;
      EXPECT_EQ(armless.in_chain[i], 1) << "plane " << i;
    }
  }
  EXPECT_GT(arm_planes, 0);
  EXPECT_GT(kept_planes, 0);
  for (const std::vector<int>& chain : armless.chains)
    for (const int p : chain) EXPECT_FALSE(arm_joint(model.planes[static_cast<std::size_t>(p)].joint)) << p;
}

TEST(CvsmGivenBody, WithoutGivenBodyClearsTheWorkersBodyOnly) {
  CvsmOptions o;
  o.stature_mm = 1800;
  o.c7_height_mm = 1530;
  o.iliac_crest_height_mm = 1080;
  o.mass_kg = 82;
  o.posture = SubjectPosture::Seated;
  o.local_budget = 21;
  o.heading = HeadingRange::Front;
  const CvsmOptions w = without_given_body(o);
  EXPECT_FALSE(w.stature_mm);
  EXPECT_FALSE(w.c7_height_mm);
  EXPECT_FALSE(w.iliac_crest_height_mm);
  EXPECT_FALSE(w.mass_kg);
  // The rest is the station's, not the worker's body: kept.
  EXPECT_EQ(w.posture, SubjectPosture::Seated);
  EXPECT_EQ(w.local_budget, 21);
  EXPECT_EQ(w.heading, HeadingRange::Front);
  EXPECT_EQ(o.stature_mm, 1800);  // a copy: the given options stay
}

}  // namespace
}  // namespace spinewatch::cvsm_detail
