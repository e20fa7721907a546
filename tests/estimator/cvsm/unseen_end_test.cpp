// Where a view's lower outline ends on pixels it cannot tell from the
// background (estimator/src/cvsm/unseen_end.hpp): a dark seat under a
// seated worker in dark clothes.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "cvsm/unseen_end.hpp"
#include "cvsm_fixtures.hpp"

namespace spinewatch {
namespace {

using cvsm_detail::kUnseenEndGapPx;
using cvsm_detail::share_ending_on_unseen;

// The share as its definition says it, pixel by pixel: each column's
// lowest silhouette pixel, and an unseen one within the gap below it.
double reference_share(const BitMask& silhouette, const BitMask& unseen) {
  int columns = 0, on_unseen = 0;
  for (int x = 0; x < silhouette.width(); ++x) {
    int bottom = -1;
    for (int y = 0; y < silhouette.height(); ++y)
      if (silhouette.get(x, y)) bottom = y;
    if (bottom < 0) continue;
    ++columns;
    for (int y = bottom + 1; y <= bottom + kUnseenEndGapPx && y < silhouette.height(); ++y)
      if (unseen.get(x, y)) {
        ++on_unseen;
        break;
      }
  }
  return columns ? static_cast<double>(on_unseen) / columns : 0;
}

// A seated person seen from the side: trunk rows 60–179 over columns
// 130–169, thighs forward to column 209 on rows 160–179; a seat of unseen
// pixels from row `seat_row` down under columns 120–179.
struct SeatScene {
  BitMask person{kW, kH};
  BitMask unseen{kW, kH};
  explicit SeatScene(int seat_row) {
    for (int y = 60; y < 180; ++y) person.set_span(y, 130, 169);
    for (int y = 160; y < 180; ++y) person.set_span(y, 130, 209);
    for (int y = seat_row; y < 200; ++y) unseen.set_span(y, 120, 179);
  }
};

TEST(UnseenEnd, TheColumnsEndingOnADarkSeatAreItsShare) {
  // 80 columns; the 50 over the seat (130–179) end on it.
  const SeatScene seat(180);
  EXPECT_DOUBLE_EQ(share_ending_on_unseen(seat.person, seat.unseen), 50.0 / 80.0);
}

TEST(UnseenEnd, ASeatBeyondTheGapIsNotWhereThePersonEnds) {
  EXPECT_DOUBLE_EQ(share_ending_on_unseen(SeatScene(180 + kUnseenEndGapPx).person,
                                          SeatScene(180 + kUnseenEndGapPx).unseen),
                   0.0);
  EXPECT_GT(share_ending_on_unseen(SeatScene(179 + kUnseenEndGapPx).person, SeatScene(179 + kUnseenEndGapPx).unseen),
            0.0);
}

TEST(UnseenEnd, NothingUnseenEmptyOrAnotherSizeIsZero) {
  const SeatScene seat(180);
  EXPECT_EQ(share_ending_on_unseen(seat.person, BitMask(kW, kH)), 0.0);
  EXPECT_EQ(share_ending_on_unseen(BitMask(kW, kH), seat.unseen), 0.0);
  EXPECT_EQ(share_ending_on_unseen(seat.person, BitMask(kW / 2, kH / 2)), 0.0);
}

TEST(UnseenEnd, MatchesThePixelByPixelDefinitionOnRandomMasks) {
  std::mt19937 rng(7);
  std::bernoulli_distribution person_px(0.3), unseen_px(0.2);
  for (int trial = 0; trial < 20; ++trial) {
    BitMask person(kW, kH), unseen(kW, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        if (person_px(rng)) person.set(x, y);
        else if (unseen_px(rng)) unseen.set(x, y);
      }
    EXPECT_DOUBLE_EQ(share_ending_on_unseen(person, unseen), reference_share(person, unseen)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace spinewatch
