#pragma once
// A synthetic scene for the silhouette tests: a textured wall, a
// person-like shape darker than it, sensor noise and exposure gain. The
// per-pixel builders are compiled optimised in every build
// (synthetic_scene.cpp, library spinewatch_synthetic_scene): the tests that
// compose thousands of frames would otherwise run at the test code's -O0
// under the sanitizers (tests/CMakeLists.txt).
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/frames/frame.hpp"
#include "bit_mask_mat.hpp"

namespace spinewatch::test::synthetic {

inline constexpr int kW = 320, kH = 240;

cv::Mat background_image();

// A smooth wall (a gradient and faint noise, as a painted wall lit from
// one side): what bootstrapping can predict behind a subject.
cv::Mat smooth_background();

// A person-like shape (head, trunk, legs) darker than the background, with shading.
inline cv::Mat person_mask(int dx = 0) {
  cv::Mat m(kH, kW, CV_8U, cv::Scalar(0));
  cv::ellipse(m, {160 + dx, 40}, {14, 18}, 0, 0, 360, 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(135 + dx, 58, 50, 90), 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(138 + dx, 148, 18, 92), 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(164 + dx, 148, 18, 92), 255, cv::FILLED);
  return m;
}

cv::Mat compose(const cv::Mat& bg, const cv::Mat& person, double gain, double noise, std::mt19937& rng);

inline LumaView view_of(const cv::Mat& m) { return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

std::int64_t differing(const BitMask& a, const cv::Mat& b);

// The scene lit unevenly: `drop` at the right edge, half of it at the left.
cv::Mat relit(const cv::Mat& bg, double drop);
// Daylight from a window at the right edge fading: `drop` there, none at
// the left edge, so no single exposure gain describes the change.
cv::Mat window(const cv::Mat& bg, double drop);
// A 0/255 image as a mask, and back.
using test::to_mask;
using test::to_mat;

}  // namespace spinewatch::test::synthetic

namespace spinewatch::test::synthetic {

// Colour: a YUYV image from a luma image and one chroma (U, V) per pixel
// (CV_8UC2), U and V averaged over each pixel pair as a camera's 4:2:2 does.
struct YuyvImage {
  std::vector<std::uint8_t> bytes;
  LumaView view() const { return {bytes.data(), kW, kH, 2 * kW, 2}; }
};

YuyvImage to_yuyv(const cv::Mat& luma, const cv::Mat& chroma);

// A coloured scene: the wall's luma `bg` with chroma `wall_uv`; the person
// (mask) with luma `person_luma` (negative: the wall's own, clothing that
// matches the wall in brightness) and chroma `person_uv`; `shadow` (mask)
// dims the wall by `shadow_factor`, luma and chroma offsets alike, as light
// does. Noise on luma and on chroma.
struct ColourScene {
  cv::Vec2b wall_uv{118, 142};   // a warm beige
  cv::Vec2b person_uv{150, 112}; // a blue shirt
  int person_luma = 70;
  cv::Rect poster;                // a patch of the wall in poster_uv (empty: none)
  cv::Vec2b poster_uv{110, 150};
  double shadow_factor = 0.65;
  double noise = 2.0, chroma_noise = 1.0;
};

YuyvImage compose_colour(const cv::Mat& bg, const cv::Mat& person, const cv::Mat& shadow,
                          const ColourScene& scene, std::mt19937& rng);

}  // namespace spinewatch::test::synthetic
