// Where the person's outline runs along an edge of the scene itself
// (SilhouetteResult::scene_edge, estimator/src/silhouette/scene_edges.hpp):
// against a reference built from OpenCV's Sobel, and on a scene where the
// person sits behind a desk's end.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "silhouette/scene_edges.hpp"
#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "synthetic_scene.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;

BackgroundModel model_of(const cv::Mat& background) {
  BackgroundModel model;
  EXPECT_TRUE(model.set(view_of(background), BackgroundSource::Stored).ok());
  return model;
}

// Every pixel of the person with a 4-neighbour outside it, away from the
// image's border, where OpenCV's 3×3 Sobel of the background reaches
// `min_gradient`.
cv::Mat reference_scene_edges(const cv::Mat& person, const cv::Mat& background, int min_gradient) {
  cv::Mat gx, gy;
  // Exact in 32-bit float (at most 4 × 255 per axis).
  cv::Sobel(background, gx, CV_32F, 1, 0, 3);
  cv::Sobel(background, gy, CV_32F, 0, 1, 3);
  cv::Mat out(person.size(), CV_8U, cv::Scalar(0));
  for (int y = 1; y < person.rows - 1; ++y)
    for (int x = 1; x < person.cols - 1; ++x) {
      if (!person.at<std::uint8_t>(y, x)) continue;
      const bool outline = !person.at<std::uint8_t>(y - 1, x) || !person.at<std::uint8_t>(y + 1, x) ||
                           !person.at<std::uint8_t>(y, x - 1) || !person.at<std::uint8_t>(y, x + 1);
      const int a = static_cast<int>(gx.at<float>(y, x)), b = static_cast<int>(gy.at<float>(y, x));
      if (outline && a * a + b * b >= min_gradient * min_gradient) out.at<std::uint8_t>(y, x) = 255;
    }
  return out;
}

// Random backgrounds with steps and texture, random blobs reaching every
// border and word boundary: pixel for pixel the reference's.
TEST(SceneEdges, EqualsASobelReference) {
  std::mt19937 rng(11);
  int marked_total = 0;
  for (const int width : {320, 130, 64}) {
    for (int trial = 0; trial < 6; ++trial) {
      cv::Mat background(60, width, CV_8U);
      cv::randu(background, 90, 110);
      std::uniform_int_distribution<int> x_at(0, width - 1), y_at(0, 59), level(0, 255);
      for (int k = 0; k < 4; ++k)
        cv::rectangle(background, cv::Rect(x_at(rng), y_at(rng), 1 + x_at(rng) / 2, 1 + y_at(rng) / 2),
                      level(rng), cv::FILLED);
      cv::Mat person(60, width, CV_8U, cv::Scalar(0));
      for (int k = 0; k < 5; ++k)
        cv::ellipse(person, {x_at(rng), y_at(rng)}, {1 + x_at(rng) / 4, 1 + y_at(rng) / 3}, 0, 0, 360, 255,
                    cv::FILLED);
      person.row(0).setTo(255);  // the border rows and columns are never marked
      person.col(width - 1).setTo(255);
      const BackgroundModel model = model_of(background);
      BitMask marked;
      silhouette_detail::mark_scene_edges(to_mask(person), model, silhouette_detail::kSceneEdgeGradient, marked);
      const cv::Mat expected = reference_scene_edges(person, background, silhouette_detail::kSceneEdgeGradient);
      EXPECT_EQ(cv::countNonZero(to_mat(marked) != expected), 0) << "width " << width << " trial " << trial;
      marked_total += cv::countNonZero(expected);
    }
  }
  EXPECT_GT(marked_total, 100);  // the comparison met marked pixels, not only blank ones
}

// A person darker than the wall, seated behind a desk whose end (a face
// 50 grey levels darker than the wall) hides everything right of column
// 200 below row 150: the silhouette's outline there runs along the
// desk's edge and is marked; on the wall it is not.
TEST(SceneEdges, TheOutlineOnADesksEndIsMarkedAndOnTheWallNot) {
  cv::Mat background = smooth_background();
  background(cv::Rect(200, 150, kW - 200, kH - 150)) -= 50;
  cv::Mat person(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(person, cv::Rect(140, 60, 40, 120), 255, cv::FILLED);   // trunk
  cv::rectangle(person, cv::Rect(140, 160, 100, 20), 255, cv::FILLED);  // thigh under the desk
  person(cv::Rect(200, 150, kW - 200, kH - 150)) = 0;                   // hidden by it
  cv::Mat frame = background.clone();
  frame.setTo(40, person);
  SilhouetteExtractor extractor{SilhouetteOptions{}};
  ASSERT_TRUE(extractor.set_background(view_of(background)).ok());
  const SilhouetteResult r = extractor.extract(view_of(frame));
  ASSERT_EQ(r.status, SilhouetteStatus::Person);
  int on_desk = 0, on_wall = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (!r.scene_edge.get(x, y)) continue;
      (x == 199 && y >= 160 && y < 180 ? on_desk : on_wall) += 1;
    }
  EXPECT_EQ(on_desk, 20);  // the thigh's end, every row
  EXPECT_EQ(on_wall, 0);
}

}  // namespace
}  // namespace spinewatch
