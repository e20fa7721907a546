// Colour in the silhouette (issue 15, item 2): the colour threshold's fast
// path against its reference, its decisions on hand-made pixel pairs, and
// whole silhouettes of a shirt as bright as the wall, a cast shadow, and a
// grey worker on a grey wall (where a shadow cannot be told from clothing
// and nothing is removed).
#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "silhouette/threshold_row.hpp"
#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "synthetic_scene.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;
using silhouette_detail::ThresholdRow;

TEST(ThresholdColour, FastPathEqualsTheReference) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> byte(0, 255), near(-24, 24);
  for (int width : {320, 64, 100, 38, 14}) {
    for (int trial = 0; trial < 60; ++trial) {
      const auto w = static_cast<std::size_t>(width);
      std::vector<std::uint8_t> bg(w), cbg(w), frame(2 * w);
      ThresholdRow row;
      row.gain_q7 = trial == 0 ? 0 : trial == 1 ? 255 : std::uniform_int_distribution<int>(64, 192)(rng);
      row.threshold = std::uniform_int_distribution<int>(1, 60)(rng);
      row.chroma_threshold = trial == 2 ? 0 : trial == 3 ? 255 : std::uniform_int_distribution<int>(1, 40)(rng);
      row.shadow_q7 = trial == 4 ? 128 : trial == 5 ? 0 : std::uniform_int_distribution<int>(20, 120)(rng);
      for (std::size_t x = 0; x < w; ++x) {
        bg[x] = static_cast<std::uint8_t>(byte(rng));
        cbg[x] = static_cast<std::uint8_t>(x % 3 == 0 ? 128 : 128 + near(rng) * 3);
        // Luma near the decision for half the pixels, near a shadow's for others.
        const int scaled = (row.gain_q7 * bg[x]) / 128;
        const int f = x % 4 == 0 ? byte(rng) : x % 4 == 1 ? scaled * 2 / 3 + near(rng) / 4 : scaled + near(rng);
        frame[2 * x] = static_cast<std::uint8_t>(std::clamp(f, 0, 255));
        // Chroma near the background's scaled by the pair's brightness, or anything.
        const int c = x % 5 == 0 ? byte(rng) : 128 + (cbg[x] - 128) * 2 / 3 + near(rng) / 3;
        frame[2 * x + 1] = static_cast<std::uint8_t>(std::clamp(c, 0, 255));
      }
      row.frame = frame.data();
      row.frame_step = 2;
      row.background = bg.data();
      row.chroma_background = cbg.data();
      row.width = width;
      std::vector<std::uint64_t> fast((w + 63) / 64, ~0ULL), ref(fast.size(), ~0ULL);
      silhouette_detail::threshold_row(row, fast.data());
      silhouette_detail::threshold_row_reference(row, ref.data());
      ASSERT_EQ(fast, ref) << "width " << width << " trial " << trial;
    }
  }
}

// One pixel pair, both pixels alike, against a background pair; true when
// both pixels come out foreground (they always agree here), through the
// fast path and the reference.
bool foreground(int y_bg, int u_bg, int v_bg, int y, int u, int v, int shadow_q7 = 64, int gain_q7 = 128) {
  // A 16-pixel row, so the fast path runs on it too.
  std::vector<std::uint8_t> bg(16, static_cast<std::uint8_t>(y_bg)), cbg(16), frame(32);
  for (int x = 0; x < 16; ++x) {
    cbg[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(x % 2 ? v_bg : u_bg);
    frame[static_cast<std::size_t>(2 * x)] = static_cast<std::uint8_t>(y);
    frame[static_cast<std::size_t>(2 * x + 1)] = static_cast<std::uint8_t>(x % 2 ? v : u);
  }
  ThresholdRow row;
  row.frame = frame.data();
  row.frame_step = 2;
  row.background = bg.data();
  row.chroma_background = cbg.data();
  row.width = 16;
  row.gain_q7 = gain_q7;
  row.threshold = 28;
  row.chroma_threshold = 12;
  row.shadow_q7 = shadow_q7;
  std::uint64_t fast = 0, ref = 0;
  silhouette_detail::threshold_row(row, &fast);
  silhouette_detail::threshold_row_reference(row, &ref);
  EXPECT_EQ(fast, ref);
  EXPECT_TRUE(ref == 0 || ref == 0xFFFF) << std::hex << ref;
  return ref == 0xFFFF;
}

TEST(ThresholdColour, DecidesByColourAndTellsShadowsFromPeople) {
  // Beige wall at 180: U 118, V 142 (offsets −10, +14).
  EXPECT_FALSE(foreground(180, 118, 142, 181, 119, 141)) << "the wall itself";
  EXPECT_TRUE(foreground(180, 118, 142, 180, 150, 112)) << "a blue shirt as bright as the wall";
  EXPECT_FALSE(foreground(180, 118, 142, 117, 122, 137)) << "the wall in shadow: 0.65 of its luma and chroma";
  EXPECT_TRUE(foreground(180, 118, 142, 117, 122, 137, 128)) << "shadow_ratio 1: shadows are person";
  EXPECT_TRUE(foreground(180, 118, 142, 54, 125, 132)) << "darker than the darkest shadow (0.3)";
  EXPECT_TRUE(foreground(180, 118, 142, 117, 128, 128)) << "as dark as a shadow but grey: not the wall's colour";
  EXPECT_TRUE(foreground(180, 118, 142, 117, 124, 133))
      << "darker, of a similar hue but not the wall's closely (skin on beige): the luma decides";
  EXPECT_FALSE(foreground(180, 118, 142, 153, 120, 140, 64, 109)) << "an exposure drop the gain follows";
  // A grey wall: a darker grey is a shadow or a grey shirt; it stays person.
  EXPECT_TRUE(foreground(180, 128, 128, 117, 128, 128)) << "grey on grey is kept";
  EXPECT_FALSE(foreground(180, 128, 128, 182, 128, 128)) << "the grey wall itself";
}

const cv::Mat kNobody(kH, kW, CV_8U, cv::Scalar(0));

SilhouetteExtractor learnt_colour(const cv::Mat& bg, const ColourScene& scene, std::mt19937& rng,
                                  SilhouetteOptions options = {}) {
  SilhouetteExtractor ex(options);
  for (int i = 0; i < options.learn_frames; ++i) ex.extract(compose_colour(bg, kNobody, cv::Mat(), scene, rng).view());
  EXPECT_TRUE(ex.background_model().has_chroma());
  return ex;
}

TEST(SilhouetteColour, AShirtAsBrightAsTheWallSeparatesByColour) {
  std::mt19937 rng(21);
  const cv::Mat bg = smooth_background();
  ColourScene scene;
  scene.person_luma = -1;  // the wall's own brightness
  const cv::Mat person = person_mask();
  SilhouetteOptions luma_only;
  luma_only.chroma_threshold = 0;
  for (const bool colour : {true, false}) {
    SilhouetteExtractor ex = learnt_colour(bg, scene, rng, colour ? SilhouetteOptions{} : luma_only);
    const auto r = ex.extract(compose_colour(bg, person, cv::Mat(), scene, rng).view());
    if (colour) {
      EXPECT_EQ(r.status, SilhouetteStatus::Person);
      // The outline is found to within a pixel pair's chroma either side.
      EXPECT_LT(differing(r.mask, person), cv::countNonZero(person) / 20);
    } else {
      EXPECT_EQ(r.status, SilhouetteStatus::NoPerson) << "luma alone cannot see it";
    }
  }
}

// A soft-edged shadow beside and below the person, as a lamp casts it.
cv::Mat shadow_beside(const cv::Mat& person) {
  cv::Mat shadow;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 30, 0, 1, 10);
  cv::warpAffine(person, shadow, shift, person.size());
  return shadow;
}

TEST(SilhouetteColour, AShadowInTheWallsColourIsNotPerson) {
  std::mt19937 rng(22);
  const cv::Mat bg = smooth_background();
  const ColourScene scene;
  const cv::Mat person = person_mask();
  const cv::Mat shadow = shadow_beside(person);
  cv::Mat shadow_only = shadow & ~person;
  SilhouetteOptions keep_shadows;
  keep_shadows.shadow_ratio = 1.0;
  for (const bool remove : {true, false}) {
    SilhouetteExtractor ex = learnt_colour(bg, scene, rng, remove ? SilhouetteOptions{} : keep_shadows);
    const auto r = ex.extract(compose_colour(bg, person, shadow, scene, rng).view());
    ASSERT_NE(r.status, SilhouetteStatus::NoPerson);
    std::int64_t in_shadow = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) in_shadow += shadow_only.at<std::uint8_t>(y, x) && r.mask.get(x, y);
    const int shadow_px = cv::countNonZero(shadow_only);
    if (remove) {
      EXPECT_LT(in_shadow, shadow_px / 50) << "of " << shadow_px << " shadow pixels";
      EXPECT_LT(differing(r.mask, person), cv::countNonZero(person) / 20);
    } else {
      EXPECT_GT(in_shadow, shadow_px * 9 / 10) << "shadow_ratio 1 keeps it";
    }
  }
}

TEST(SilhouetteColour, AGreyWorkerOnAGreyWallIsNotTakenForAShadow) {
  std::mt19937 rng(23);
  const cv::Mat bg = smooth_background();
  ColourScene scene;
  scene.wall_uv = {128, 128};
  scene.person_uv = {128, 128};
  scene.person_luma = 120;  // about 0.65 of the wall: a shadow's brightness
  scene.poster = {10, 10, 40, 40};  // colour elsewhere in the scene, so the colour test runs
  SilhouetteExtractor ex = learnt_colour(bg, scene, rng);
  const cv::Mat person = person_mask();
  const auto r = ex.extract(compose_colour(bg, person, cv::Mat(), scene, rng).view());
  EXPECT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_LT(differing(r.mask, person), cv::countNonZero(person) / 20);
}

// The background keeps the chroma of YUYV frames, learnt and adapted; a
// grey background has none, nor one of neutral chroma.
TEST(BackgroundChroma, IsLearntFromYuyvAndFollowsTheLight) {
  std::mt19937 rng(24);
  const cv::Mat bg = smooth_background();
  ColourScene scene;
  scene.chroma_noise = 0;
  BackgroundAdaptation a;
  a.learn_frames = 4;
  a.adapt_frames = 2;
  BackgroundModel model(a);
  for (int i = 0; i < 4; ++i) model.learn(compose_colour(bg, kNobody, cv::Mat(), scene, rng).view());
  ASSERT_TRUE(model.has_chroma());
  EXPECT_EQ(model.chroma_row(100)[40], 118);
  EXPECT_EQ(model.chroma_row(100)[41], 142);
  // The whole scene dimmed to 0.8 (the chroma offsets too): the model follows.
  ColourScene dim = scene;
  dim.wall_uv = {static_cast<std::uint8_t>(128 - 8), static_cast<std::uint8_t>(128 + 11)};
  const BitMask none(kW, kH);
  cv::Mat dimmed;
  bg.convertTo(dimmed, CV_8U, 0.8);
  for (int i = 0; i < 2 * 16; ++i) model.update(compose_colour(dimmed, kNobody, cv::Mat(), dim, rng).view(), none, none, 0.8);
  EXPECT_EQ(model.chroma_row(100)[40], 120);
  EXPECT_EQ(model.chroma_row(100)[41], 139);
  const cv::Mat grey = bg.clone();
  ASSERT_TRUE(model.set(view_of(grey), BackgroundSource::Stored).ok());
  EXPECT_FALSE(model.has_chroma());
  // YUYV without colour (chroma 128 everywhere: a monochrome camera) has
  // nothing for the colour test either.
  ColourScene neutral = scene;
  neutral.wall_uv = {128, 128};
  ASSERT_TRUE(model.set(compose_colour(bg, kNobody, cv::Mat(), neutral, rng).view(), BackgroundSource::Stored).ok());
  EXPECT_FALSE(model.has_chroma());
}

}  // namespace
}  // namespace spinewatch
