#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "luma_png.hpp"
#include "spinewatch/phantom/phantom.hpp"
#include "test_support.hpp"

namespace spinewatch::phantom {
namespace {

PhantomSequence make(const std::string& scenario, std::uint32_t seed = 1, std::optional<int> frames = std::nullopt,
                     int empty_frames = 10) {
  PhantomOptions options;
  options.scenario = scenario;
  options.seed = seed;
  options.frames = frames;
  options.empty_frames = empty_frames;
  auto sequence = PhantomSequence::create(options);
  if (!sequence) throw std::runtime_error(sequence.error().message);
  return std::move(sequence).value();
}

bool equal(const cv::Mat& a, const cv::Mat& b) { return a.size() == b.size() && cv::countNonZero(a != b) == 0; }

// Where the noise-free render differs from the empty scene.
cv::Mat person_region(const PhantomSequence& sequence, const PhantomFrame& frame, View view) {
  cv::Mat diff;
  cv::absdiff(frame.clean[static_cast<int>(view)], sequence.background(view), diff);
  return diff > 10;
}

TEST(PhantomRender, SameSeedSameBytesAnyOrder) {
  const PhantomSequence a = make("combined", 7);
  const PhantomSequence b = make("combined", 7);
  const int index = 10 + 45;
  const PhantomFrame first = a.render(index);
  (void)b.render(3);  // rendering other frames first changes nothing
  (void)b.render(index + 1);
  const PhantomFrame second = b.render(index);
  for (int view = 0; view < 2; ++view) EXPECT_TRUE(equal(first.luma[view], second.luma[view])) << view;
}

TEST(PhantomRender, DifferentSeedDifferentNoise) {
  const PhantomFrame a = make("upright", 1).render(12);
  const PhantomFrame b = make("upright", 2).render(12);
  for (int view = 0; view < 2; ++view) {
    cv::Mat diff;
    cv::absdiff(a.luma[view], b.luma[view], diff);
    // Noise differs nearly everywhere, not in a few pixels.
    EXPECT_GT(cv::countNonZero(diff), int(diff.total() / 2)) << view;
  }
}

TEST(PhantomRender, NoiseHasTheRequestedSpread) {
  PhantomOptions options;
  options.scenario = "upright";
  options.flicker = 0;
  options.noise_sigma = 4.0;
  auto sequence = PhantomSequence::create(options);
  ASSERT_TRUE(sequence);
  const PhantomFrame frame = sequence->render(20);
  for (int view = 0; view < 2; ++view) {
    cv::Mat noise;
    cv::subtract(frame.luma[view], frame.clean[view], noise, cv::noArray(), CV_32F);
    cv::Scalar mean, stddev;
    cv::meanStdDev(noise, mean, stddev);
    EXPECT_NEAR(mean[0], 0, 0.2);
    EXPECT_NEAR(stddev[0], 4.0, 0.3);
  }
  options.noise_sigma = 0;
  auto quiet = PhantomSequence::create(options);
  ASSERT_TRUE(quiet);
  const PhantomFrame still = quiet->render(20);
  EXPECT_TRUE(equal(still.luma[0], still.clean[0]));
}

TEST(PhantomRender, FlickerIsAGlobalGainPerFrame) {
  PhantomOptions options;
  options.noise_sigma = 0;
  options.flicker = 0.05;
  auto sequence = PhantomSequence::create(options);
  ASSERT_TRUE(sequence);
  double lowest = 2, highest = 0;
  for (int i = 0; i < 10; ++i) {
    const PhantomFrame frame = sequence->render(i);
    const double gain = cv::mean(frame.luma[0])[0] / cv::mean(frame.clean[0])[0];
    EXPECT_GT(gain, 0.95 - 0.01);
    EXPECT_LT(gain, 1.05 + 0.01);
    lowest = std::min(lowest, gain);
    highest = std::max(highest, gain);
  }
  EXPECT_GT(highest - lowest, 0.01);
}

TEST(PhantomRender, EmptyFramesShowTheSceneAndAreLost) {
  const PhantomSequence sequence = make("flexion", 3, 30, 4);
  ASSERT_EQ(sequence.frame_count(), 34);
  const PhantomFrame empty = sequence.render(3);
  EXPECT_TRUE(equal(empty.clean[0], sequence.background(View::Frontal)));
  EXPECT_EQ(cv::countNonZero(empty.person[1]), 0);
  EXPECT_EQ(empty.truth.state, TrackingState::Lost);
  EXPECT_FALSE(empty.truth.neck);
  EXPECT_FALSE(empty.truth.vertebrae);
  const PhantomFrame person = sequence.render(4);
  EXPECT_EQ(person.truth.state, TrackingState::Tracking);
  EXPECT_GT(cv::countNonZero(person.person[0]), 1000);
}

// The person changes the frame only where he is, and one pixel around (the
// lens softens his outline): a cluttered room's edges elsewhere are the
// stored background's pixels exactly, or they would join the silhouette.
TEST(PhantomRender, TheRoomDoesNotChangeWhenThePersonWalksIn) {
  PhantomOptions options;
  options.scenario = "flexion";
  options.frames = 20;
  options.room = RoomKind::Cluttered;
  const PhantomSequence sequence = PhantomSequence::create(options).value();
  const PhantomFrame frame = sequence.render(options.empty_frames + 10);
  for (View view : kViews) {
    const int v = static_cast<int>(view);
    cv::Mat near;
    cv::dilate(frame.person[v] > 0, near, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
    const cv::Mat changed = frame.clean[v] != sequence.background(view);
    EXPECT_EQ(cv::countNonZero(changed & ~near), 0) << int(view);
    EXPECT_GT(cv::countNonZero(changed & near), 2000) << int(view);
  }
}

TEST(PhantomRender, NeckAndWaistLieInsideThePersonInBothViews) {
  for (const Scenario& scenario : scenarios()) {
    // Without furniture: the desk hides the seated typist's waist from the
    // frontal camera, as it should (variety_test.cpp).
    PhantomOptions options;
    options.scenario = scenario.name;
    options.seed = 4;
    options.frames = 30;
    options.empty_frames = 2;
    options.desk = false;
    const PhantomSequence sequence = PhantomSequence::create(options).value();
    for (int i : {2, 2 + 15, 2 + 29}) {
      const PhantomFrame frame = sequence.render(i);
      ASSERT_TRUE(frame.truth.neck && frame.truth.waist);
      for (View view : kViews) {
        const cv::Mat region = person_region(sequence, frame, view);
        for (const Eigen::Vector3d& point : {*frame.truth.neck, *frame.truth.waist}) {
          auto pixel = sequence.camera(view).project(point);
          ASSERT_TRUE(pixel);
          const int x = int(std::lround(pixel->x())), y = int(std::lround(pixel->y()));
          ASSERT_TRUE(x >= 0 && x < region.cols && y >= 0 && y < region.rows) << scenario.name << " frame " << i;
          EXPECT_TRUE(region.at<std::uint8_t>(y, x)) << scenario.name << " frame " << i << " view " << int(view) << " at "
                                                      << x << "," << y;
        }
      }
    }
  }
}

TEST(PhantomRender, PersonContrastsWithTheBackground) {
  const PhantomSequence sequence = make("flexion");
  const PhantomFrame frame = sequence.render(10 + 45);
  for (View view : kViews) {
    const cv::Mat region = person_region(sequence, frame, view);
    const int area = cv::countNonZero(region);
    EXPECT_GT(area, 2500) << int(view);
    EXPECT_LT(area, int(region.total() / 2)) << int(view);
    cv::Mat diff;
    cv::absdiff(frame.clean[static_cast<int>(view)], sequence.background(view), diff);
    EXPECT_GT(cv::mean(diff, region)[0], 50) << int(view);
    // Shaded, not a flat fill.
    cv::Scalar mean, stddev;
    cv::meanStdDev(frame.clean[static_cast<int>(view)], mean, stddev, frame.person[static_cast<int>(view)] > 0);
    EXPECT_GT(stddev[0], 3) << int(view);
  }
}

TEST(PhantomRender, ScenariosRenderTheRequestedFrames) {
  for (const Scenario& scenario : scenarios()) {
    EXPECT_GE(scenario.default_frames, 60) << scenario.name;
    EXPECT_LE(scenario.default_frames, 120) << scenario.name;
    const PhantomSequence defaults = make(std::string(scenario.name));
    EXPECT_EQ(defaults.frame_count(), 10 + scenario.default_frames) << scenario.name;
    const PhantomSequence short_one = make(std::string(scenario.name), 1, 8, 0);
    ASSERT_EQ(short_one.frame_count(), 8);
    EXPECT_EQ(short_one.render(7).truth.state, TrackingState::Tracking);
    EXPECT_EQ(short_one.render(7).luma[1].size(), cv::Size(kImageWidth, kImageHeight));
  }
  PhantomOptions options;
  options.scenario = "backflip";
  auto bad = PhantomSequence::create(options);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("unknown scenario \"backflip\""), std::string::npos);
  EXPECT_NE(bad.error().message.find("seated_flexion"), std::string::npos);
}

TEST(PhantomRender, ScenariosMoveTheWayTheyAreNamed) {
  auto mid = [](const char* name) {
    const PhantomSequence s = make(name, 1, 61, 0);
    return s.ground_truth(30);
  };
  const Posture flexion = mid("flexion");
  EXPECT_NEAR(std::acos(flexion.neck_dir->y()) * 180 / M_PI, 50, 0.5);
  EXPECT_GT(flexion.neck_dir->x(), 0.5);
  EXPECT_LT(mid("lateral_left").neck_dir->z(), -0.3);
  EXPECT_GT(mid("lateral_right").neck_dir->z(), 0.3);
  EXPECT_NEAR(std::acos(mid("seated_flexion").neck_dir->y()) * 180 / M_PI, 40, 0.5);
  // Twist: at a quarter of the movement T1 has turned +20° about the vertical.
  const PhantomSequence twist = make("twist", 1, 61, 0);
  const Posture quarter = twist.ground_truth(15);
  double twist_sum = 0;
  for (const auto& a : quarter.angles) twist_sum += a.twist;
  EXPECT_NEAR(twist_sum, 20, 0.5);
  // Fast: 40° reached within 0.5 s of starting to bend.
  const PhantomSequence fast = make("fast", 1, 60, 0);
  double peak = 0;
  int first_moving = -1, peak_frame = -1;
  for (int i = 0; i < 60; ++i) {
    const double angle = std::acos(fast.ground_truth(i).neck_dir->y()) * 180 / M_PI;
    if (first_moving < 0 && angle > 0.01) first_moving = i;
    if (angle > peak) peak = angle, peak_frame = i;
  }
  EXPECT_NEAR(peak, 40, 0.5);
  EXPECT_LE(peak_frame - (first_moving - 1), 15);
}

TEST(PhantomRender, SavesExampleImages) {
  // SPINEWATCH_PHANTOM_IMAGES=docs/images regenerates the documentation's
  // pictures; otherwise they go to a temporary directory.
  test::TempDir tmp;
  const char* env = std::getenv("SPINEWATCH_PHANTOM_IMAGES");
  const std::filesystem::path dir = env ? std::filesystem::path(env) : tmp.path();
  const PhantomSequence flexion = make("flexion");
  const PhantomSequence seated = make("seated_flexion");
  const PhantomFrame bend = flexion.render(10 + 45);  // the deepest bend, 50°
  const PhantomFrame sit = seated.render(10 + 45);
  const FrameFormat grey = FrameFormat::packed(PixelFormat::GREY, kImageWidth, kImageHeight);
  auto as_frame = [&](const cv::Mat& m) {
    return Frame::copy_of(grey, {}, std::span<const std::uint8_t>(m.data, m.total()));
  };
  const std::pair<std::string, cv::Mat> images[] = {{"phantom-frontal.png", bend.luma[0]},
                                                    {"phantom-lateral.png", bend.luma[1]},
                                                    {"phantom-seated-lateral.png", sit.luma[1]}};
  for (const auto& [name, luma] : images) {
    const Frame frame = as_frame(luma);
    ASSERT_TRUE(test::save_luma_png(frame.luma(), dir / name)) << name;
    const cv::Mat back = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    EXPECT_TRUE(equal(back, luma)) << name;
  }
}

}  // namespace
}  // namespace spinewatch::phantom
