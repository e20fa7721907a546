// What a view cannot tell from the background (SilhouetteResult::unseen):
// the opening against OpenCV's, and the unseen pixels of a scene where a
// part of the person differs from the background by less than the
// threshold (dark trousers before a black chair; docs/cvsm.md, "A black
// chair").
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "synthetic_scene.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;

// Random masks of every kind the opening meets: speckle, solid regions
// with ragged edges, one-pixel lines; widths with a ragged last word.
TEST(OpenSquare, EqualsOpenCvsOpening) {
  std::mt19937 rng(5);
  for (const int width : {320, 130, 64, 7})
    for (const int radius : {1, 2})
      for (const double density : {0.3, 0.7, 0.95}) {
        cv::Mat m(40, width, CV_8U);
        std::bernoulli_distribution on(density);
        for (int y = 0; y < m.rows; ++y)
          for (int x = 0; x < m.cols; ++x) m.at<std::uint8_t>(y, x) = on(rng) ? 255 : 0;
        cv::line(m, {0, 20}, {width - 1, 25}, 255, 1);
        cv::rectangle(m, cv::Rect(width / 4, 5, std::max(1, width / 3), 12), 255, cv::FILLED);
        BitMask bits = to_mask(m);
        open_square(bits, radius);
        cv::Mat reference;
        cv::morphologyEx(m, reference, cv::MORPH_OPEN,
                         cv::getStructuringElement(cv::MORPH_RECT, {2 * radius + 1, 2 * radius + 1}));
        EXPECT_EQ(cv::countNonZero(to_mat(bits) != reference), 0) << "width " << width << " radius " << radius << " density " << density;
      }
}

// The stored background; the person at 60 grey levels below it, a region
// below the person 20 below it (under the threshold of 28, over half of
// it), and a one-pixel band around the person 20 below it (a blurred
// outline).
struct ChairScene {
  cv::Mat background = background_image();
  cv::Mat frame = background.clone();
  cv::Mat person = person_mask();
  cv::Mat trousers = cv::Mat(kH, kW, CV_8U, cv::Scalar(0));
  cv::Mat rim;
  ChairScene() {
    cv::rectangle(trousers, cv::Rect(120, 150, 80, 40), 255, cv::FILLED);
    trousers.setTo(0, person);
    cv::dilate(person, rim, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    rim.setTo(0, person);
    rim.setTo(0, trousers);
    cv::Mat darker;
    cv::subtract(background, cv::Scalar(60), darker);
    darker.copyTo(frame, person);
    cv::subtract(background, cv::Scalar(20), darker);
    darker.copyTo(frame, trousers);
    darker.copyTo(frame, rim);
  }
};

// An extractor on a stored background image (luma, or YUYV with chroma).
SilhouetteExtractor on_stored(const LumaView& background) {
  SilhouetteOptions options;
  options.background = BackgroundMode::Image;
  SilhouetteExtractor extractor(options);
  EXPECT_TRUE(extractor.set_background(background).ok());
  return extractor;
}

TEST(Silhouette, WhatTheViewCannotTellFromTheBackgroundIsUnseen) {
  const ChairScene scene;
  SilhouetteExtractor extractor = on_stored(view_of(scene.background));
  const SilhouetteResult r = extractor.extract(view_of(scene.frame));
  ASSERT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_LE(differing(r.mask, scene.person), cv::countNonZero(scene.person) / 200);  // the closing fills corners
  // The region is unseen, whole: it is more than 3 px thick everywhere.
  const cv::Mat unseen = to_mat(r.unseen);
  EXPECT_EQ(cv::countNonZero(unseen & scene.trousers), cv::countNonZero(scene.trousers));
  // The outline's band, the person and the rest of the scene are not
  // (but for the band's pixels beside the region, which belong to it).
  cv::Mat beside;
  cv::dilate(scene.trousers, beside, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  EXPECT_GT(cv::countNonZero(scene.rim & ~beside), 300);
  EXPECT_EQ(cv::countNonZero(unseen & scene.rim & ~beside), 0);
  EXPECT_EQ(cv::countNonZero(unseen & scene.person), 0);
  EXPECT_EQ(cv::countNonZero(unseen & ~beside), 0);

  // Half the threshold is where it starts: 13 grey levels below the
  // background are nothing, 15 are unseen (threshold 28).
  for (const auto& [below, seen] : {std::pair{13, false}, std::pair{15, true}}) {
    cv::Mat frame = scene.frame.clone(), darker;
    cv::subtract(scene.background, cv::Scalar(below), darker);
    darker.copyTo(frame, scene.trousers);
    const SilhouetteResult at = extractor.extract(view_of(frame));
    EXPECT_EQ(at.unseen.count() > 0, seen) << below;
  }
}

TEST(Silhouette, NothingIsUnseenWithoutAPersonOrInColour) {
  const ChairScene scene;
  SilhouetteExtractor grey = on_stored(view_of(scene.background));
  const SilhouetteResult empty = grey.extract(view_of(scene.background));
  EXPECT_EQ(empty.status, SilhouetteStatus::NoPerson);
  EXPECT_EQ(empty.unseen.count(), 0);
  // In colour (a warm wall) the chroma tells the person from the
  // background, and a shadow differs by its luma alone: nothing is unseen.
  std::vector<std::uint8_t> frame(static_cast<std::size_t>(kW * kH * 2)), bg(frame.size());
  for (std::size_t i = 1; i < frame.size(); i += 4) {
    frame[i] = bg[i] = 118;          // U
    frame[i + 2] = bg[i + 2] = 140;  // V
  }
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      frame[static_cast<std::size_t>((y * kW + x) * 2)] = scene.frame.at<std::uint8_t>(y, x);
      bg[static_cast<std::size_t>((y * kW + x) * 2)] = scene.background.at<std::uint8_t>(y, x);
    }
  SilhouetteExtractor colour = on_stored({bg.data(), kW, kH, kW * 2, 2});
  const SilhouetteResult c = colour.extract({frame.data(), kW, kH, kW * 2, 2});
  ASSERT_EQ(c.status, SilhouetteStatus::Person);
  EXPECT_EQ(c.unseen.count(), 0);
}

}  // namespace
}  // namespace spinewatch
