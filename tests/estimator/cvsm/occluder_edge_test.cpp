// What an occluder hides (estimator/src/cvsm/occluder_edge.hpp) and the
// cost that does not count the model there (XorCost::set_hidden).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cvsm/occluder_edge.hpp"
#include "cvsm/xor_cost.hpp"
#include "cvsm_fixtures.hpp"
#include "cvsm/pelvis_in_view.hpp"

namespace spinewatch {
namespace {

using cvsm_detail::find_occluder_edge;
using cvsm_detail::hidden_below;

// A seated person's frontal outline behind a desk: head, shoulders and a
// trunk whose lower outline is the desk's edge at row `edge`.
BitMask cut_trunk(int edge) {
  BitMask m(kW, kH);
  for (int y = 60; y < 80; ++y) m.set_span(y, 150, 170);  // head
  for (int y = 80; y <= edge; ++y) m.set_span(y, 120, 200);  // trunk and arms
  return m;
}

TEST(OccluderEdge, FindsTheDeskEdgeAcrossTheTrunkHighAboveTheFloor) {
  const auto e = find_occluder_edge(cut_trunk(150), 230);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->x0, 120);
  EXPECT_EQ(e->x1, 200);
  EXPECT_NEAR(e->row(160), 150, 0.01);
  EXPECT_NEAR(e->slope, 0, 1e-9);
}

TEST(OccluderEdge, FindsATiltedEdge) {
  // A rolled camera: the desk's edge runs 0.2 rows per column.
  BitMask m(kW, kH);
  for (int x = 120; x <= 200; ++x)
    for (int y = 80; y <= 140 + static_cast<int>(std::lround(0.2 * (x - 120))); ++y) m.set(x, y);
  const auto e = find_occluder_edge(m, 230);
  ASSERT_TRUE(e);
  EXPECT_NEAR(e->slope, 0.2, 0.02);
}

TEST(OccluderEdge, NotFeetOnTheFloor) {
  // The same straight lower outline, at the floor: a person standing or
  // sitting with the feet together, nothing hidden.
  EXPECT_FALSE(find_occluder_edge(cut_trunk(150), 152));
  // Just above the floor by less than 15 % of the person's height (90 rows above the edge).
  EXPECT_FALSE(find_occluder_edge(cut_trunk(150), 150 + 0.15 * 90));
  EXPECT_TRUE(find_occluder_edge(cut_trunk(150), 150 + 0.2 * 90));
}

TEST(OccluderEdge, NotABodysOwnStraightOutline) {
  // A seated thigh seen from the side: straight underneath, but the shank
  // goes down from its end to the floor: the person does not end there.
  BitMask m = cut_trunk(150);
  for (int y = 151; y < 230; ++y) m.set_span(y, 190, 200);
  EXPECT_FALSE(find_occluder_edge(m, 230));
  // An arm held out sideways, straight underneath, nothing under it, the
  // legs far below beside it.
  BitMask arm(kW, kH);
  for (int y = 60; y < 229; ++y) arm.set_span(y, 150, 190);  // trunk and legs to the floor
  for (int y = 90; y < 100; ++y) arm.set_span(y, 60, 150);   // the arm
  EXPECT_FALSE(find_occluder_edge(arm, 230));
  EXPECT_FALSE(find_occluder_edge(BitMask(kW, kH), 230));
}

TEST(OccluderEdge, APersonEndingInMidAirIsHeldByWhatTheBackgroundHides) {
  // A rounded lower outline ending high above the floor: its flat bottom
  // is taken for an edge (a seat or a stool the background holds is under
  // it), but only as wide as that flat bottom ...
  BitMask round(kW, kH);
  for (int x = 120; x <= 200; ++x) {
    const double u = (x - 160) / 40.0;
    for (int y = 80; y <= 150 - static_cast<int>(30 * u * u); ++y) round.set(x, y);
  }
  const auto e = find_occluder_edge(round, 230);
  ASSERT_TRUE(e);
  EXPECT_LT(e->x1 - e->x0, 40);
  // ... and not on the floor.
  EXPECT_FALSE(find_occluder_edge(round, 160));
}

TEST(OccluderEdge, NotTheImagesLowerBorder) {
  // Cut by the image's border, not by a desk.
  EXPECT_FALSE(find_occluder_edge(cut_trunk(kH - 1), kH + 100));
  EXPECT_TRUE(find_occluder_edge(cut_trunk(kH - 10), kH + 100));
}

TEST(OccluderEdge, HidesBelowTheEdgeAndBesideItButNotTheSilhouette) {
  const BitMask m = cut_trunk(150);
  const auto e = find_occluder_edge(m, 230);
  ASSERT_TRUE(e);
  BitMask hidden;
  hidden_below(*e, m, hidden);
  EXPECT_FALSE(hidden.get(160, 150));  // the edge row is the person's
  EXPECT_TRUE(hidden.get(160, 151));
  EXPECT_TRUE(hidden.get(160, kH - 1));
  EXPECT_TRUE(hidden.get(120 - 20, 200));  // a quarter of the edge's 81 columns beyond it
  EXPECT_FALSE(hidden.get(120 - 21, 200));
  EXPECT_FALSE(hidden.get(160, 100));
  for (int y = 0; y < kH; ++y)
    for (int w = 0; w < m.words_per_row(); ++w) EXPECT_EQ(m.row(y)[w] & hidden.row(y)[w], 0U);
}

// Forearms resting on the desk beside the trunk, past a gap of background
// under each armpit, and a hand farther out: the straight run is the
// trunk's, but the edge's line cuts the others too, and the cut span
// reaches them.
TEST(OccluderEdge, TheCutSpanReachesForearmsEndingOnTheEdgeBesideTheTrunk) {
  BitMask m = cut_trunk(150);
  for (int y = 80; y <= 140; ++y) {  // the gaps under the armpits, columns 116–119 and 201–204
    m.set_span(y, 116, 119);
    m.set_span(y, 201, 204);
  }
  for (int y = 90; y <= 151; ++y) {  // forearms ending on the edge (a row lower: hands on the desk)
    m.set_span(y, 100, 115);
    m.set_span(y, 205, 220);
  }
  for (int y = 120; y <= 150; ++y) m.set_span(y, 230, 235);  // a hand farther out
  const auto e = find_occluder_edge(m, 230);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->x0, 120);
  EXPECT_EQ(e->x1, 200);
  EXPECT_EQ(e->cut_x0, 100);
  EXPECT_EQ(e->cut_x1, 235);
  BitMask run, cut;
  hidden_below(*e, m, run);
  hidden_below(*e, m, cut, cvsm_detail::HiddenSpan::Cut);
  // The run's span: 120 − 20 … 200 + 20 (a quarter of its 81 columns).
  EXPECT_TRUE(run.get(220, 200));
  EXPECT_FALSE(run.get(221, 200));
  // The cut span: 100 − 20 … 235 + 20.
  EXPECT_TRUE(cut.get(80, 200));
  EXPECT_FALSE(cut.get(79, 200));
  EXPECT_TRUE(cut.get(255, 200));
  EXPECT_FALSE(cut.get(256, 200));
  EXPECT_FALSE(cut.get(110, 151));  // the forearm's own pixel stays the person's
}

// The hidden pixels' count against its reference: every pixel of the
// model's render and the silhouette compared one by one, the hidden ones
// skipped; on every row and on a row sample, with and without pruning.
TEST(XorCost, HiddenPixelsAreNotCountedLikeTheReference) {
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject();
  const Views truth = render(rig, model, bend(20, 5, 0));
  // Hide everything below row 150 that is not silhouette, in both views.
  BitMask hidden[2] = {BitMask(kW, kH), BitMask(kW, kH)};
  const BitMask* sils[2] = {&truth.frontal, &truth.lateral};
  for (int v = 0; v < 2; ++v)
    for (int y = 150; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        if (!sils[v]->get(x, y)) hidden[v].set(x, y);
  XorCost cost(rig, kW, kH);
  cost.set_silhouettes(truth.frontal, truth.lateral);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-20, 50), lat(-20, 20), shift(-80, 80);
  std::vector<Eigen::Vector3d> pts;
  int differs_from_unhidden = 0;
  for (int i = 0; i < 30; ++i) {
    CvsmPose p = bend(angle(rng), lat(rng), lat(rng) * 0.5);
    p.translation = {shift(rng), shift(rng) * 0.5, shift(rng)};
    control_points(model, pose_vertebrae(model, generic_spine_spec(), p), pts);
    for (const int step : {1, 4}) {
      cost.set_row_step(step);
      cost.set_hidden(nullptr, nullptr);
      const XorCounts plain = cost.evaluate(model, pts);
      cost.set_hidden(&hidden[0], &hidden[1]);
      const XorCounts fast = cost.evaluate(model, pts);
      std::int64_t ref = 0;
      for (int v = 0; v < 2; ++v) {
        const BitMask drawn = cost.render(model, pts, kViews[static_cast<std::size_t>(v)]);
        for (int y = 0; y < kH; y += step)
          for (int x = 0; x < kW; ++x) ref += !hidden[v].get(x, y) && drawn.get(x, y) != sils[v]->get(x, y);
      }
      EXPECT_EQ(fast.total(), ref) << "candidate " << i << ", row step " << step;
      EXPECT_LE(fast.total(), plain.total());
      differs_from_unhidden += fast.total() != plain.total();
      // Pruned: a lower bound above the limit.
      const XorCounts pruned = cost.evaluate(model, pts, ref / 2);
      if (ref / 2 < ref) {
        EXPECT_TRUE(pruned.pruned);
        EXPECT_GT(pruned.total(), ref / 2);
        EXPECT_LE(pruned.total(), ref);
      }
    }
  }
  EXPECT_GT(differs_from_unhidden, 30);  // the hidden rows held model pixels
}

// The pelvis out of the picture (estimator/src/cvsm/pelvis_in_view.hpp):
// a seated subject's spine moved down until its hips project below the
// image, against a silhouette that runs into the bottom row or ends above it.
TEST(PelvisInView, OutOnlyWhereTheHipsProjectBeyondTheEdgeTheSilhouetteRunsInto) {
  using cvsm_detail::pelvis_out_of_view;
  const CameraRig rig = CameraRig::default_rig();
  const BodyModel model = other_subject(SubjectPosture::Seated);
  const SpinePose seated = pose_vertebrae(model, generic_spine_spec(), CvsmPose{});
  const Views views = render(rig, model, CvsmPose{});
  // In view: the whole seated body is in the picture.
  EXPECT_FALSE(pelvis_out_of_view(rig.frontal, views.frontal, model, seated));
  EXPECT_FALSE(pelvis_out_of_view(rig.lateral, views.lateral, model, seated));
  SpinePose low = seated;
  for (auto& v : low) v.body_center.y() -= 2000;  // the hips far below the image
  BitMask cut(kW, kH);
  for (int y = 100; y < kH; ++y) cut.set_span(y, 120, 200);  // a trunk the bottom edge cuts
  BitMask ends(kW, kH);
  for (int y = 100; y < kH - 1; ++y) ends.set_span(y, 120, 200);  // ... that ends one row above it
  BitMask speck(kW, kH);
  speck.set_span(kH - 1, 150, 150 + cvsm_detail::kPelvisCutMinPx - 2);  // noise on the bottom row
  for (const CameraModel* camera : {&rig.frontal, &rig.lateral}) {
    EXPECT_TRUE(pelvis_out_of_view(*camera, cut, model, low));
    EXPECT_FALSE(pelvis_out_of_view(*camera, ends, model, low));
    EXPECT_FALSE(pelvis_out_of_view(*camera, speck, model, low));
    EXPECT_FALSE(pelvis_out_of_view(*camera, cut, model, seated));  // cut, but the hips are in the picture
    EXPECT_FALSE(pelvis_out_of_view(*camera, BitMask{}, model, low));
  }
}

TEST(PelvisInView, TheEdgeAPointIsFarthestBeyond) {
  using cvsm_detail::edge_beyond;
  using cvsm_detail::ImageEdge;
  EXPECT_FALSE(edge_beyond({0, 0}, kW, kH));
  EXPECT_FALSE(edge_beyond({kW - 1, kH - 1}, kW, kH));
  EXPECT_EQ(edge_beyond({100, kH}, kW, kH), ImageEdge::Bottom);
  EXPECT_EQ(edge_beyond({100, -1}, kW, kH), ImageEdge::Top);
  EXPECT_EQ(edge_beyond({-1, 100}, kW, kH), ImageEdge::Left);
  EXPECT_EQ(edge_beyond({kW, 100}, kW, kH), ImageEdge::Right);
  // A camera on its side: the body runs out to the left, a little below too.
  EXPECT_EQ(edge_beyond({-50, kH + 10}, kW, kH), ImageEdge::Left);
}

}  // namespace
}  // namespace spinewatch
