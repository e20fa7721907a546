// The background lifecycle (background_model.hpp, background_bootstrap.hpp):
// adaptation outside the person against a plain floating-point reference,
// the person and a passer-by never learnt, a moved object absorbed, the
// whole background re-learnt after an empty spell, and a background
// bootstrapped with the subject in view from the first frame.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "synthetic_scene.hpp"

namespace spinewatch {
namespace {

using namespace test::synthetic;

TEST(DilateSquare, EqualsOpenCvsRectangularDilation) {
  std::mt19937 rng(7);
  for (int radius : {0, 1, 2, 3, 5, 8, 13}) {
    cv::Mat m(kH, kW, CV_8U, cv::Scalar(0));
    std::uniform_int_distribution<int> x(0, kW - 1), y(0, kH - 1);
    for (int i = 0; i < 40; ++i) m.at<std::uint8_t>(y(rng), x(rng)) = 255;
    cv::rectangle(m, cv::Rect(60, 50, 30, 10), 255, cv::FILLED);
    cv::Mat expected;
    cv::dilate(m, expected, cv::getStructuringElement(cv::MORPH_RECT, {2 * radius + 1, 2 * radius + 1}), {-1, -1}, 1,
               cv::BORDER_CONSTANT, 0);
    BitMask out(kW, kH);
    dilate_square(to_mask(m), radius, out);
    EXPECT_EQ(cv::countNonZero(to_mat(out) != expected), 0) << "radius " << radius;
  }
}

// The fixed-point running average against the plain one it implements:
// b ← b + α (f − b) per frame, every pixel outside the protected region.
TEST(BackgroundModel, AdaptationFollowsItsFloatingPointReference) {
  const cv::Mat bg = background_image();
  BackgroundAdaptation options;
  options.adapt_frames = 30;
  options.relearn_empty_frames = 0;
  BackgroundModel model(options);
  ASSERT_TRUE(model.set(view_of(bg), BackgroundSource::Stored));
  cv::Mat reference;
  bg.convertTo(reference, CV_64F);
  const double alpha = 1.0 / options.adapt_frames;
  const BitMask none;
  for (int i = 0; i < 240; ++i) {
    const cv::Mat frame = relit(bg, 0.35 * i / 239.0);
    model.update(view_of(frame), none, none);
    cv::Mat f;
    frame.convertTo(f, CV_64F);
    reference += alpha * (f - reference);
  }
  // The model updates each row once every 16 frames: it lags the
  // reference by up to 16 frames of a drift of 0.35 × 190 / 240 ≈ 0.28
  // grey a frame.
  double worst = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) worst = std::max(worst, std::abs(model.row(y)[x] - reference.at<double>(y, x)));
  EXPECT_LT(worst, 5.5);
  EXPECT_EQ(model.counters().updates, 240U);
}

TEST(BackgroundModel, ThePersonAndTheMarginAroundThemAreNeverLearnt) {
  const cv::Mat bg = background_image();
  BackgroundAdaptation options;
  options.adapt_frames = 10;
  options.margin_px = 6;
  BackgroundModel model(options);
  ASSERT_TRUE(model.set(view_of(bg), BackgroundSource::Stored));
  std::mt19937 rng(1);
  const cv::Mat person = person_mask();
  const BitMask person_bits = to_mask(person);
  for (int i = 0; i < 300; ++i) model.update(view_of(compose(bg, person, 1.0, 2.0, rng)), person_bits, person_bits);
  cv::Mat near;
  cv::dilate(person, near, cv::getStructuringElement(cv::MORPH_RECT, {13, 13}));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (near.at<std::uint8_t>(y, x)) {
        ASSERT_EQ(model.row(y)[x], bg.at<std::uint8_t>(y, x)) << x << "," << y;
      }
    }
}

TEST(Silhouette, FollowsUnevenLightDriftWithoutLosingThePerson) {
  const cv::Mat bg = background_image();
  SilhouetteOptions options;
  options.adaptation.adapt_frames = 60;
  SilhouetteExtractor ex(options);
  ASSERT_TRUE(ex.set_background(view_of(bg)));
  SilhouetteOptions frozen = options;
  frozen.adaptation.adapt_frames = 0;
  SilhouetteExtractor still(frozen);
  ASSERT_TRUE(still.set_background(view_of(bg)));
  std::mt19937 rng(2);
  const int frames = 1800;  // 60 s at 30 fps; the light falls by 35 % on average: not at all at one side, 70 % at the other
  std::int64_t worst = 0, worst_frozen = 0;
  for (int i = 0; i < frames; ++i) {
    const int dx = static_cast<int>(20 * std::sin(i * 0.05));
    const cv::Mat person = person_mask(dx);
    const cv::Mat frame = compose(window(bg, 0.7 * i / (frames - 1.0)), person, 1.0, 2.0, rng);
    const SilhouetteResult r = ex.extract(view_of(frame));
    const SilhouetteResult f = still.extract(view_of(frame));
    // As the estimator does when tracking: outside the fitted outline
    // (here the true one).
    const BitMask fitted = to_mask(person);
    ex.adapt(view_of(frame), &fitted);
    still.adapt(view_of(frame), &fitted);
    ASSERT_EQ(r.status, SilhouetteStatus::Person) << "frame " << i;
    worst = std::max(worst, differing(r.mask, person));
    const std::int64_t frozen_error = f.status == SilhouetteStatus::Person ? differing(f.mask, person) : cv::countNonZero(person);
    worst_frozen = std::max(worst_frozen, frozen_error);
  }
  // Gain compensation alone (adaptation off) cannot follow an uneven change.
  EXPECT_LT(worst, 150) << "adapting";
  EXPECT_GT(worst_frozen, 4 * worst) << "without adaptation";
}

TEST(Silhouette, APasserByIsNotLearntButAMovedObjectIsAbsorbed) {
  const cv::Mat bg = background_image();
  SilhouetteOptions options;
  options.adaptation.adapt_frames = 30;
  options.adaptation.foreground_slowdown = 20;
  SilhouetteExtractor ex(options);
  ASSERT_TRUE(ex.set_background(view_of(bg)));
  std::mt19937 rng(3);
  const cv::Mat person = person_mask();
  // A box put down beside the person (a chair moved) stays foreground for
  // a while, then becomes part of the scene.
  cv::Mat box(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(box, cv::Rect(250, 150, 40, 60), 255, cv::FILLED);
  int box_px_at_30 = 0, box_px_at_3000 = 0;
  for (int i = 0; i <= 3000; ++i) {
    const cv::Mat frame = compose(bg, person | box, 1.0, 2.0, rng);
    (void)ex.extract(view_of(frame));
    ex.adapt(view_of(frame));
    if (i == 30 || i == 3000) {
      int n = 0;
      for (int y = 150; y < 210; ++y)
        for (int x = 250; x < 290; ++x) n += std::abs(ex.background_model().row(y)[x] - bg.at<std::uint8_t>(y, x)) < 28;
      (i == 30 ? box_px_at_30 : box_px_at_3000) = n;
    }
  }
  EXPECT_GT(box_px_at_30, 40 * 60 * 9 / 10) << "a passer-by's time in view is not enough to learn it";
  EXPECT_LT(box_px_at_3000, 40 * 60 / 10) << "an object left for 100 s becomes the scene";
}

TEST(Silhouette, AnEmptySpellRelearnsTheWholeBackground) {
  const cv::Mat bg = background_image();
  SilhouetteOptions options;
  options.adaptation.adapt_frames = 0;  // only the re-learning can change it
  options.adaptation.relearn_empty_frames = 60;
  options.learn_frames = 10;
  SilhouetteExtractor ex(options);
  ASSERT_TRUE(ex.set_background(view_of(bg)));
  std::mt19937 rng(4);
  const cv::Mat lamp = relit(bg, -0.15);  // a lamp switched on: brighter, unevenly
  const cv::Mat nobody(kH, kW, CV_8U, cv::Scalar(0));
  // The 60th empty frame starts the re-learning, the 10th frame after it ends it.
  auto empty_frame = [&] {
    const cv::Mat frame = compose(lamp, nobody, 1.0, 2.0, rng);
    (void)ex.extract(view_of(frame));
    ex.adapt(view_of(frame));
  };
  for (int i = 0; i < 68; ++i) empty_frame();
  EXPECT_EQ(ex.background_model().counters().relearns, 0U);
  empty_frame();
  EXPECT_EQ(ex.background_model().counters().relearns, 1U);
  double error = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) error += std::abs(ex.background_model().row(y)[x] - lamp.at<std::uint8_t>(y, x));
  EXPECT_LT(error / (kW * kH), 1.5);
  // The person walks back in: found against the new scene.
  const SilhouetteResult r = ex.extract(view_of(compose(lamp, person_mask(), 1.0, 2.0, rng)));
  EXPECT_EQ(r.status, SilhouetteStatus::Person);
  EXPECT_LT(differing(r.mask, person_mask()), 150);
}

TEST(Silhouette, SomeoneInViewFromTheStartIsBootstrappedFromTheirMovement) {
  const cv::Mat bg = smooth_background();
  SilhouetteOptions options;
  SilhouetteExtractor ex(options);
  std::mt19937 rng(5);
  int first_person = -1, no_background = 0;
  for (int i = 0; i < 120 && first_person < 0; ++i) {
    // Side to side by 40 px over 2 s, as a worker reaching along a bench.
    const int dx = static_cast<int>(40 * std::sin(i * 2 * M_PI / 60));
    const cv::Mat person = person_mask(dx);
    const SilhouetteResult r = ex.extract(view_of(compose(bg, person, 1.0, 2.0, rng)));
    if (r.status == SilhouetteStatus::NoBackground) ++no_background;
    if (r.status == SilhouetteStatus::Person) {
      first_person = i;
      EXPECT_LT(differing(r.mask, person), cv::countNonZero(person) / 10) << "frame " << i;
    }
    ASSERT_NE(r.status, SilhouetteStatus::NoPerson) << "frame " << i << ": never a silent no_person";
  }
  EXPECT_GE(first_person, 10) << "not before the learning frames showed it moved";
  EXPECT_LT(first_person, 90) << "within 3 s";
  EXPECT_GT(no_background, 0);
  EXPECT_EQ(ex.background_model().source(), BackgroundSource::Bootstrapped);
  EXPECT_EQ(ex.background_model().counters().bootstraps, 1U);
}

TEST(Silhouette, WithoutBootstrappingTheLearntMeanStands) {
  const cv::Mat bg = smooth_background();
  SilhouetteOptions options;
  options.bootstrap = false;
  SilhouetteExtractor ex(options);
  std::mt19937 rng(5);
  for (int i = 0; i < 10; ++i) (void)ex.extract(view_of(compose(bg, person_mask(2 * i), 1.0, 2.0, rng)));
  EXPECT_EQ(ex.background_model().source(), BackgroundSource::Learnt);
}

}  // namespace
}  // namespace spinewatch

namespace spinewatch {
namespace {

using namespace test::synthetic;

// The live view's "learn the background again" (PostureEstimator::relearn_background):
// the stored background is dropped and the next empty frames are learnt
// as at start; a stored-image mode refuses.
TEST(Silhouette, ARelearnOnRequestLearnsTheSceneAsItIsNow) {
  const cv::Mat bg = background_image();
  SilhouetteOptions options;
  options.adaptation.adapt_frames = 0;
  options.learn_frames = 10;
  SilhouetteExtractor ex(options);
  ASSERT_TRUE(ex.set_background(view_of(bg)));
  std::mt19937 rng(9);
  const cv::Mat lamp = relit(bg, -0.2);
  const cv::Mat nobody(kH, kW, CV_8U, cv::Scalar(0));
  ASSERT_TRUE(ex.relearn_background());
  EXPECT_FALSE(ex.background_ready());
  EXPECT_EQ(ex.background_model().source(), BackgroundSource::None);
  for (int i = 0; i < 10; ++i) {
    const SilhouetteResult r = ex.extract(view_of(compose(lamp, nobody, 1.0, 2.0, rng)));
    EXPECT_EQ(r.status, SilhouetteStatus::LearningBackground) << "frame " << i;
  }
  EXPECT_EQ(ex.background_model().source(), BackgroundSource::Learnt);
  double error = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) error += std::abs(ex.background_model().row(y)[x] - lamp.at<std::uint8_t>(y, x));
  EXPECT_LT(error / (kW * kH), 1.5);
  const SilhouetteResult r = ex.extract(view_of(compose(lamp, person_mask(), 1.0, 2.0, rng)));
  EXPECT_EQ(r.status, SilhouetteStatus::Person);

  SilhouetteOptions image;
  image.background = BackgroundMode::Image;
  SilhouetteExtractor stored(image);
  ASSERT_TRUE(stored.set_background(view_of(bg)));
  EXPECT_FALSE(stored.relearn_background());
  EXPECT_TRUE(stored.background_ready());
}

}  // namespace
}  // namespace spinewatch
