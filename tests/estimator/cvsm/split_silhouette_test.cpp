// A pair whose silhouette is smaller than the subject's as built is weighed
// against the built outline only when the silhouette is whole
// (XorCounts::cost_against, docs/cvsm.md "Measuring along the world's
// vertical"): a foreshortened trunk shrinks the outline while the misfit
// along it stays. A silhouette the extractor flags (two blobs, cut by the
// image's border) is smaller because part of the person is missing, and is
// weighed against itself.
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "trust_run.hpp"

namespace spinewatch {
namespace {

LumaView view_of(const cv::Mat& m) { return LumaView{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

// The silhouette without its columns from `first_column` on: a side of the
// person gone, along an edge no occluder's rule reads as a desk's (those
// are near level).
SilhouetteResult cut_beside(SilhouetteResult s, int first_column) {
  for (int y = 0; y < s.mask.height(); ++y)
    for (int x = first_column; x < s.mask.width(); ++x) s.mask.set(x, y, false);
  s.pixels = s.mask.count();
  return s;
}

TEST(SplitSilhouette, APartOfThePersonMissingIsWeighedAgainstItself) {
  phantom::PhantomOptions po;
  po.scenario = "upright";
  po.subject = test::load_named_subject("ansur-15936");
  po.frames = 16;
  auto seq = phantom::PhantomSequence::create(po);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  SilhouetteExtractor frontal{SilhouetteOptions{}}, lateral{SilhouetteOptions{}};
  CvsmTracker whole(seq->options().rig, CvsmOptions{}), split(seq->options().rig, CvsmOptions{});
  SilhouetteResult last_frontal, last_lateral;
  for (int i = 0; i < seq->frame_count(); ++i) {
    const phantom::PhantomFrame f = seq->render(i);
    last_frontal = frontal.extract(view_of(f.luma[0]));
    last_lateral = lateral.extract(view_of(f.luma[1]));
    const CvsmResult a = whole.track(last_frontal, last_lateral);
    const CvsmResult b = split.track(last_frontal, last_lateral);
    ASSERT_EQ(a.state, b.state) << "frame " << i;
  }
  ASSERT_EQ(last_frontal.status, SilhouetteStatus::Person);
  // The frontal view loses one side of the person: the model still draws
  // it, so the misfit grows by what is gone while the silhouette shrinks by
  // it.
  int left = last_frontal.mask.width(), right = -1;
  for (int y = 0; y < last_frontal.mask.height(); ++y)
    for (int x = 0; x < last_frontal.mask.width(); ++x)
      if (last_frontal.mask.get(x, y)) {
        left = std::min(left, x);
        right = std::max(right, x);
      }
  // 55 % of its width kept. Measured: both fits 0.457 of their own
  // silhouettes, tracking against the built outline, lost flagged (45 %
  // kept: 0.547, too much gone to stand against either; 62 %: 0.324, stands
  // against its own).
  SilhouetteResult missing = cut_beside(last_frontal, left + (right - left) * 55 / 100);
  const CvsmResult unflagged = whole.track(missing, last_lateral);
  missing.status = SilhouetteStatus::TwoBlobs;
  const CvsmResult flagged = split.track(missing, last_lateral);
  std::printf("one side gone: cost %.3f (weighed against the built outline: %s), flagged %.3f (%s)\n",
              unflagged.fit.cost, to_string(unflagged.state).data(), flagged.fit.cost, to_string(flagged.state).data());
  // Both fit the same silhouettes and report their own share of them.
  EXPECT_GT(flagged.fit.cost, CvsmOptions{}.lost_cost);
  EXPECT_NEAR(flagged.fit.cost, unflagged.fit.cost, 0.02);
  EXPECT_EQ(*flagged.fit.flag, "two_blobs");
  // Whole, the smaller outline is read as foreshortened and the pair
  // stands against the built one; flagged, it does not.
  EXPECT_EQ(unflagged.state, TrackingState::Tracking) << "cost " << unflagged.fit.cost;
  EXPECT_EQ(flagged.state, TrackingState::Lost) << "cost " << flagged.fit.cost;
}

}  // namespace
}  // namespace spinewatch
