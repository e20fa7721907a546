// Silhouette extraction: background learning, exposure compensation,
// cleaning to the person's blob, status flags, and agreement with an
// OpenCV reference (absdiff / threshold / morphology / connectedComponents).
#include <algorithm>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "silhouette/threshold_row.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "synthetic_scene.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;

SilhouetteExtractor learned(const cv::Mat& bg, std::mt19937& rng, SilhouetteOptions opt = {}) {
  SilhouetteExtractor ex(opt);
  for (int i = 0; i < opt.learn_frames; ++i) {
    const cv::Mat empty = compose(bg, cv::Mat(kH, kW, CV_8U, cv::Scalar(0)), 1.0, 2.0, rng);
    EXPECT_EQ(ex.extract(view_of(empty)).status, SilhouetteStatus::LearningBackground);
  }
  EXPECT_TRUE(ex.background_ready());
  return ex;
}


TEST(BitMask, PacksRowsIntoWords) {
  BitMask m(320, 2);
  EXPECT_EQ(m.words_per_row(), 5);
  m.set_span(1, 60, 130);
  EXPECT_EQ(m.count(), 71);
  EXPECT_EQ(m.count_row(0), 0);
  EXPECT_TRUE(m.get(60, 1));
  EXPECT_TRUE(m.get(130, 1));
  EXPECT_FALSE(m.get(59, 1));
  EXPECT_FALSE(m.get(131, 1));
  m.set_span(0, -5, 400);  // clipped
  EXPECT_EQ(m.count_row(0), 320);
}

TEST(Silhouette, LearnsBackgroundAndFindsThePersonUnderFlicker) {
  std::mt19937 rng(1);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  const cv::Mat person = person_mask();
  const auto truth = cv::countNonZero(person);
  for (double gain : {0.97, 1.0, 1.03, 1.08}) {
    const cv::Mat frame = compose(bg, person, gain, 2.0, rng);
    const SilhouetteResult r = ex.extract(view_of(frame));
    EXPECT_EQ(r.status, SilhouetteStatus::Person) << gain;
    EXPECT_NEAR(r.gain, gain, 0.01);
    EXPECT_EQ(r.pixels, r.mask.count());
    EXPECT_LT(differing(r.mask, person), truth / 100) << "gain " << gain;
  }
}

TEST(Silhouette, AgreesWithOpenCvReference) {
  std::mt19937 rng(2);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  const cv::Mat frame = compose(bg, person_mask(20), 1.03, 3.0, rng);
  const SilhouetteResult r = ex.extract(view_of(frame));

  // Reference: the same gain, then absdiff / threshold / closing / largest component.
  cv::Mat bgf, scaled, diff, fg, closed, labels, stats, centroids;
  cv::Mat learned_bg(kH, kW, CV_8U, const_cast<std::uint8_t*>(ex.background().data()));
  learned_bg.convertTo(scaled, CV_32F, r.gain);
  frame.convertTo(bgf, CV_32F);
  cv::absdiff(bgf, scaled, diff);
  cv::threshold(diff, fg, 28.0, 255, cv::THRESH_BINARY);
  fg.convertTo(fg, CV_8U);
  cv::morphologyEx(fg, closed, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_CROSS, {3, 3}), {-1, -1}, 1,
                   cv::BORDER_REPLICATE);
  const int n = cv::connectedComponentsWithStats(closed, labels, stats, centroids, 8);
  int best = 1;
  for (int i = 2; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) > stats.at<int>(best, cv::CC_STAT_AREA)) best = i;
  const cv::Mat ref = labels == best;
  EXPECT_LE(differing(r.mask, ref), cv::countNonZero(ref) / 200) << "more than 0.5 % of pixels differ";
}

TEST(Silhouette, YuyvViewGivesTheSameMaskAsGrey) {
  std::mt19937 rng(3);
  const cv::Mat bg = background_image();
  const cv::Mat frame = compose(bg, person_mask(), 1.0, 2.0, rng);
  std::vector<std::uint8_t> yuyv(static_cast<std::size_t>(kW * kH * 2), 128), bg_yuyv(yuyv.size(), 128);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      yuyv[static_cast<std::size_t>((y * kW + x) * 2)] = frame.at<std::uint8_t>(y, x);
      bg_yuyv[static_cast<std::size_t>((y * kW + x) * 2)] = bg.at<std::uint8_t>(y, x);
    }
  SilhouetteOptions opt;
  opt.background = BackgroundMode::Image;
  SilhouetteExtractor grey(opt), packed(opt);
  ASSERT_TRUE(grey.set_background(view_of(bg)).ok());
  ASSERT_TRUE(packed.set_background({bg_yuyv.data(), kW, kH, kW * 2, 2}).ok());
  const auto a = grey.extract(view_of(frame));
  const auto b = packed.extract({yuyv.data(), kW, kH, kW * 2, 2});
  EXPECT_EQ(a.status, SilhouetteStatus::Person);
  EXPECT_TRUE(a.mask == b.mask);
}

// The SIMD threshold against its scalar reference, bit for bit: grey and
// YUYV rows, widths with and without a ragged last word, the whole gain
// range, differences right at the threshold.
TEST(ThresholdRow, FastPathEqualsTheReference) {
  using silhouette_detail::ThresholdRow;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255), near(-40, 40);
  for (int width : {320, 64, 100, 37, 15}) {
    for (int step : {1, 2}) {
      for (int trial = 0; trial < 40; ++trial) {
        std::vector<std::uint8_t> bg(static_cast<std::size_t>(width)), frame(static_cast<std::size_t>(width * step));
        ThresholdRow row;
        row.gain_q7 = trial == 0 ? 0 : trial == 1 ? 255 : std::uniform_int_distribution<int>(64, 192)(rng);
        row.threshold = std::uniform_int_distribution<int>(1, 60)(rng);
        for (int x = 0; x < width; ++x) {
          bg[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(byte(rng));
          // Half the pixels within a few levels of the decision.
          const int scaled = (row.gain_q7 * bg[static_cast<std::size_t>(x)]) / 128;
          const int f = x % 2 ? byte(rng) : scaled + (near(rng) > 0 ? row.threshold : -row.threshold) + near(rng) / 10;
          frame[static_cast<std::size_t>(x * step)] = static_cast<std::uint8_t>(std::clamp(f, 0, 255));
        }
        row.frame = frame.data();
        row.frame_step = step;
        row.background = bg.data();
        row.width = width;
        std::vector<std::uint64_t> fast(static_cast<std::size_t>((width + 63) / 64), ~0ULL), ref(fast.size(), ~0ULL);
        silhouette_detail::threshold_row(row, fast.data());
        silhouette_detail::threshold_row_reference(row, ref.data());
        ASSERT_EQ(fast, ref) << "width " << width << " step " << step << " gain " << row.gain_q7;
      }
    }
  }
}

TEST(Silhouette, RemovesSmallBlobsAndFillsPinholes) {
  std::mt19937 rng(4);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  cv::Mat person = person_mask();
  cv::Mat frame = compose(bg, person, 1.0, 2.0, rng);
  cv::rectangle(frame, cv::Rect(20, 20, 6, 6), 0, cv::FILLED);  // a 36-pixel speck
  frame.at<std::uint8_t>(100, 160) = bg.at<std::uint8_t>(100, 160);  // a pinhole in the trunk
  const auto r = ex.extract(view_of(frame));
  EXPECT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_FALSE(r.mask.get(22, 22));
  EXPECT_TRUE(r.mask.get(160, 100));
  EXPECT_EQ(r.blobs, 1);
}

TEST(Silhouette, FlagsNoPersonTwoBlobsAndOcclusion) {
  std::mt19937 rng(5);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  const cv::Mat none(kH, kW, CV_8U, cv::Scalar(0));
  EXPECT_EQ(ex.extract(view_of(compose(bg, none, 1.02, 2.0, rng))).status, SilhouetteStatus::NoPerson);

  cv::Mat two = person_mask(-70) | person_mask(70);
  const auto r2 = ex.extract(view_of(compose(bg, two, 1.0, 2.0, rng)));
  EXPECT_EQ(r2.status, SilhouetteStatus::TwoBlobs);
  EXPECT_EQ(r2.blobs, 2);
  EXPECT_GT(r2.second_blob_px, 1000);

  const auto r3 = ex.extract(view_of(compose(bg, person_mask(-150), 1.0, 2.0, rng)));
  EXPECT_EQ(r3.status, SilhouetteStatus::Occluded);
  EXPECT_EQ(flag_of(r3.status), "occluded");
}

// Scenery the stored background does not hold — a chair moved, a bag set
// down — beside a person who sways: two_blobs while the box could still be
// someone walking in, then, once it has kept its place for
// StillScenery::kStillFrames frames, the person alone (docs/cvsm.md,
// "Silhouettes"). Before, every frame was two_blobs: on the phantom, a box
// beside the subject lost all 60 pairs of a clip.
TEST(Silhouette, AStillObjectBesideThePersonIsSceneryOnceItKeepsItsPlace) {
  std::mt19937 rng(11);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  cv::Mat box(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(box, cv::Rect(20, 140, 50, 70), 255, cv::FILLED);
  int two_blobs = 0;
  for (int i = 0; i < 3 * StillScenery::kStillFrames; ++i) {
    const int sway = (i % 5) - 2;
    const auto r = ex.extract(view_of(compose(bg, person_mask(sway) | box, 1.0, 2.0, rng)));
    if (i < StillScenery::kStillFrames) {
      EXPECT_EQ(r.status, SilhouetteStatus::TwoBlobs) << "frame " << i;
    } else {
      EXPECT_EQ(r.status, SilhouetteStatus::Person) << "frame " << i;
    }
    two_blobs += r.status == SilhouetteStatus::TwoBlobs;
    EXPECT_FALSE(r.mask.get(45, 175)) << "the box is not the person, frame " << i;
    EXPECT_TRUE(r.mask.get(160 + sway, 100)) << "frame " << i;
  }
  EXPECT_EQ(two_blobs, StillScenery::kStillFrames);
}

// A second person walking past (3 pixels a frame, about 1 m/s at this
// scale; farther away, so smaller) never keeps its place: two_blobs on
// every frame. And two people of one size, one standing still, the other
// walking: the largest blob goes from one to the other, and the one left
// out is not taken for scenery either.
TEST(Silhouette, ASecondPersonWalkingPastStaysTwoBlobs) {
  std::mt19937 rng(12);
  const cv::Mat bg = background_image();
  SilhouetteExtractor ex = learned(bg, rng);
  for (int i = 0; i < 3 * StillScenery::kStillFrames; ++i) {
    cv::Mat walker = person_mask(-110 + 3 * i);
    walker(cv::Rect(0, 120, kW, kH - 120)) = 0;  // his legs hidden: the smaller blob
    const auto r = ex.extract(view_of(compose(bg, person_mask(60) | walker, 1.0, 2.0, rng)));
    EXPECT_EQ(r.status, SilhouetteStatus::TwoBlobs) << "frame " << i;
    EXPECT_TRUE(r.mask.get(220, 100)) << "frame " << i;
  }
  SilhouetteExtractor same_size = learned(bg, rng);
  for (int i = 0; i < 3 * StillScenery::kStillFrames; ++i) {
    const auto r = same_size.extract(view_of(compose(bg, person_mask(60) | person_mask(-110 + 3 * i), 1.0, 2.0, rng)));
    if (r.status != SilhouetteStatus::TwoBlobs) {
      // Only where the largest blob stayed the walker: the one standing
      // still then counts as scenery beside him (the limit of the rule).
      EXPECT_FALSE(r.mask.get(220, 100)) << "frame " << i;
    }
  }
}

// A backdrop with a dark, textured band across the trunk's rows (a dark
// shirt or cupboard in a photographed room): the person's trunk matches it
// and the silhouette falls apart into the part above the band and the part
// below. Both are the subject; a second person beside is still two_blobs.
TEST(Silhouette, KeepsTheSubjectSplitByAMatchingBackdropAsOnePerson) {
  std::mt19937 rng(7);
  cv::Mat bg = background_image();
  for (int y = 95; y < 136; ++y)
    for (int x = 0; x < kW; ++x) bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(55 + (x * 5 + y * 3) % 11);
  SilhouetteExtractor ex = learned(bg, rng);

  const cv::Mat person = person_mask();
  const auto r = ex.extract(view_of(compose(bg, person, 1.0, 2.0, rng)));
  EXPECT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_EQ(r.blobs, 2);                          // the band did split the subject
  EXPECT_TRUE(r.mask.get(160, 40));               // the head, above the band
  EXPECT_TRUE(r.mask.get(147, 200));              // a leg, below it
  EXPECT_FALSE(r.mask.get(160, 115));             // the trunk inside the band is lost to it
  EXPECT_EQ(r.pixels, r.mask.count());

  const auto two = ex.extract(view_of(compose(bg, person_mask(-70) | person_mask(70), 1.0, 2.0, rng)));
  EXPECT_EQ(two.status, SilhouetteStatus::TwoBlobs);
  EXPECT_EQ(two.blobs, 4);
  EXPECT_GT(two.second_blob_px, 1000);
}

TEST(Silhouette, PlainThresholdAgainstUniformBackdrop) {
  std::mt19937 rng(6);
  SilhouetteOptions opt;
  opt.background = BackgroundMode::Threshold;
  SilhouetteExtractor ex(opt);
  const cv::Mat flat(kH, kW, CV_8U, cv::Scalar(190));
  const cv::Mat person = person_mask();
  const auto r = ex.extract(view_of(compose(flat, person, 1.0, 2.0, rng)));
  EXPECT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_LT(differing(r.mask, person), cv::countNonZero(person) / 100);
}

TEST(Silhouette, BadInputIsAnErrorNotACrash) {
  EXPECT_FALSE(parse_background_mode("auto").ok());
  EXPECT_NE(parse_background_mode("auto").error().message.find("silhouette.background"), std::string::npos);
  SilhouetteExtractor ex;
  EXPECT_FALSE(ex.set_background({}).ok());
  std::vector<std::uint8_t> small(16 * 8, 100);
  const auto r = ex.extract({small.data(), 16, 8, 16, 1});
  EXPECT_EQ(r.status, SilhouetteStatus::LearningBackground);
  std::vector<std::uint8_t> other(32 * 8, 100);
  EXPECT_EQ(ex.extract({other.data(), 32, 8, 32, 1}).status, SilhouetteStatus::NoPerson);  // size changed
}

}  // namespace
}  // namespace spinewatch
