// The seated spine hangs from the crown the first pair measured
// (subject_estimate.hpp, SubjectEstimate::crown_lift_mm): measured on a trunk
// bent over a desk, that crown lies below where it would be upright, and the
// spine hung from it would sit as much too low.
#include <algorithm>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cvsm/subject_estimate.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch::cvsm_detail {
namespace {

SubjectEstimate seated(double flexion_deg) {
  SubjectEstimate s;
  s.shape.posture = SubjectPosture::Seated;
  s.shape.height_mm = 1700;
  s.measured_spine = true;
  s.measured_crown_mm = 1250;
  s.crown_y = 1250;
  s.pose.flexion = flexion_deg;
  return s;
}

double lift(const SubjectEstimate& s) { return crown_lift(s, generic_cvsm_spec(), generic_spine_spec()); }

// The model's highest control point in the estimate's pose: the top of its
// head as the views draw it.
double head_top(const SubjectEstimate& s) {
  const BodyModel m = build(s, generic_cvsm_spec(), generic_spine_spec());
  std::vector<Eigen::Vector3d> points;
  control_points(m, pose_vertebrae(m, generic_spine_spec(), s.pose), points, s.pose.limbs, s.pose.heading);
  double top = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : points) top = std::max(top, p.y());
  return top;
}

double l5_height(const SubjectEstimate& s) {
  return build(s, generic_cvsm_spec(), generic_spine_spec()).neutral[kWaistIndex].body_center.y();
}

TEST(CvsmSubjectCrown, ATrunkFirstSeenBentHangsFromTheCrownItWouldHaveUpright) {
  // A seated subject whose crown upright is at 1 250 mm, bent 15° over a
  // desk (typing: 10–18°) on the pair that measures it: the views see his
  // crown lower by what the bend lowers the model's head.
  const SubjectEstimate upright = seated(0);
  EXPECT_NEAR(lift(upright), 0, 0.01);
  SubjectEstimate bent_upright_crown = seated(15);
  const double drop = head_top(upright) - head_top(bent_upright_crown);
  ASSERT_GT(drop, 8);
  SubjectEstimate seen = seated(15);
  seen.measured_crown_mm = seen.crown_y = 1250 - drop;
  // Hung from the crown as measured, his spine sits as much too low.
  EXPECT_NEAR(l5_height(seen), l5_height(upright) - drop, 0.5);
  // Hung from the crown it would have upright, it sits where it is.
  seen.crown_lift_mm = lift(seen);
  EXPECT_NEAR(l5_height(seen), l5_height(upright), 2.0);
  // A side bend lowers the crown too.
  SubjectEstimate leaning = seated(0);
  leaning.pose.lateral = 15;
  EXPECT_GT(lift(leaning), 5);
}

// Held once set: a later pair's pose is not the one the crown was measured in.
TEST(CvsmSubjectCrown, TheLiftOnceSetIsHeld) {
  SubjectEstimate s = seated(15);
  s.crown_lift_mm = 7.0;
  s.pose.flexion = 30;
  EXPECT_EQ(lift(s), 7.0);
}

// Standing, the crown is the stature the spine is placed for; with the
// generic placement or the crown cut off by the image, nothing hangs from it.
TEST(CvsmSubjectCrown, OnlyASeatedSpineHungFromAMeasuredCrownIsLifted) {
  SubjectEstimate standing = seated(15);
  standing.shape.posture = SubjectPosture::Standing;
  EXPECT_EQ(lift(standing), 0);
  SubjectEstimate generic = seated(15);
  generic.measured_spine = false;
  EXPECT_EQ(lift(generic), 0);
  SubjectEstimate cut_off = seated(15);
  cut_off.measured_crown_mm = 0;
  EXPECT_EQ(lift(cut_off), 0);
}

// A first pair fitted nearly upright lowers the crown by less than the
// crown is measured to: nothing is lifted (kMinCrownLiftMm).
TEST(CvsmSubjectCrown, ABendTheCrownsMeasurementDoesNotResolveLiftsNothing) {
  EXPECT_EQ(lift(seated(3)), 0);
  EXPECT_EQ(lift(seated(-3)), 0);
  EXPECT_GE(lift(seated(12)), kMinCrownLiftMm);
}

}  // namespace
}  // namespace spinewatch::cvsm_detail
