// A desk's end seen from the side (estimator/src/cvsm/side_cut.hpp): the
// steep straight outline on the scene's edge that hides what lies beyond.
#include <gtest/gtest.h>

#include <cmath>

#include "cvsm/side_cut.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

using cvsm_detail::add_hidden_beyond;
using cvsm_detail::find_side_cut;
using cvsm_detail::Side;

// A seated person seen from the side: head, trunk, and a thigh forward
// whose end, rows 150–179, lies on the line `end(y)` (the desk's edge).
struct SideScene {
  BitMask person{kW, kH};
  BitMask scene_edge{kW, kH};
  explicit SideScene(double slope, bool on_scene_edge = true) {
    for (int y = 40; y < 60; ++y) person.set_span(y, 140, 160);  // head
    for (int y = 60; y < 180; ++y) person.set_span(y, 130, 170);  // trunk
    for (int y = 150; y < 180; ++y) {
      const int end = 200 + static_cast<int>(std::lround(slope * (y - 150)));
      person.set_span(y, 130, end);
      if (on_scene_edge) scene_edge.set(end, y);
    }
  }
};

TEST(SideCut, FindsTheDesksEndAlongTheThighs) {
  const SideScene scene(0.3);
  const auto cut = find_side_cut(scene.person, scene.scene_edge, Side::Right);
  ASSERT_TRUE(cut);
  EXPECT_EQ(cut->y0, 150);
  EXPECT_EQ(cut->y1, 179);
  EXPECT_NEAR(cut->slope, 0.3, 0.03);
  EXPECT_NEAR(cut->column(165), 200 + 0.3 * 15, 1.0);
  EXPECT_FALSE(find_side_cut(scene.person, scene.scene_edge, Side::Left));
}

TEST(SideCut, NotAStraightOutlineOnThePlainWall) {
  // The same thigh ending on its own (nothing in the background there):
  // a straight end is not an occluder.
  const SideScene scene(0.3, false);
  EXPECT_FALSE(find_side_cut(scene.person, scene.scene_edge, Side::Right));
}

TEST(SideCut, NotAShortRunOrOneAboveTheLowerBody) {
  SideScene scene(0.0);
  // Only 7 rows of the end on the scene's edge.
  BitMask few(kW, kH);
  for (int y = 150; y < 157; ++y) few.set(200, y);
  EXPECT_FALSE(find_side_cut(scene.person, few, Side::Right));
  // The trunk's side on a door frame, above the silhouette's lower half.
  BitMask high(kW, kH);
  for (int y = 60; y < 100; ++y) high.set(170, y);
  EXPECT_FALSE(find_side_cut(scene.person, high, Side::Right));
}

TEST(SideCut, TheBendAtTheEdgesCornerIsTrimmed) {
  // The end follows the desk's slanted edge, then its vertical corner for
  // the last 6 rows: the cut is the slanted part.
  SideScene scene(0.6);
  for (int y = 174; y < 180; ++y) {
    for (int x = 0; x < kW; ++x) scene.scene_edge.set(x, y, false);
    const int end = 200 + static_cast<int>(std::lround(0.6 * (173 - 150)));
    for (int x = end + 1; x < kW; ++x) scene.person.set(x, y, false);
    scene.scene_edge.set(end, y);
  }
  const auto cut = find_side_cut(scene.person, scene.scene_edge, Side::Right);
  ASSERT_TRUE(cut);
  EXPECT_NEAR(cut->slope, 0.6, 0.06);
  EXPECT_LE(cut->y1, 176);
}

TEST(SideCut, HidesBeyondTheLineOnItsRowsAndNeverThePerson) {
  const SideScene scene(0.0);
  const auto cut = find_side_cut(scene.person, scene.scene_edge, Side::Right);
  ASSERT_TRUE(cut);
  BitMask hidden(kW, kH);
  add_hidden_beyond(*cut, scene.person, hidden);
  // Rows 150–179 and a quarter of the 30 rows (7) either side, columns
  // 201 on: 44 rows of 119 pixels.
  EXPECT_EQ(hidden.count(), 44 * (kW - 201));
  EXPECT_TRUE(hidden.get(201, 143));
  EXPECT_FALSE(hidden.get(201, 142));
  EXPECT_FALSE(hidden.get(200, 160));  // the line itself is the person's
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) EXPECT_FALSE(hidden.get(x, y) && scene.person.get(x, y));
}

}  // namespace
}  // namespace spinewatch
