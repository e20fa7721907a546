#pragma once
// A synthetic scene for the silhouette tests: a textured wall, a
// person-like shape darker than it, sensor noise and exposure gain.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/frames/frame.hpp"

namespace spinewatch::test::synthetic {

inline constexpr int kW = 320, kH = 240;

inline cv::Mat background_image() {
  cv::Mat bg(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(150 + 40 * x / kW + 20 * ((x / 16 + y / 16) % 2));
  return bg;
}

// A smooth wall (a gradient and faint noise, as a painted wall lit from
// one side): what bootstrapping can predict behind a subject.
inline cv::Mat smooth_background() {
  cv::Mat bg(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(160 + 30 * x / kW + 15 * y / kH + ((x * 7 + y * 13) % 5));
  return bg;
}

// A person-like shape (head, trunk, legs) darker than the background, with shading.
inline cv::Mat person_mask(int dx = 0) {
  cv::Mat m(kH, kW, CV_8U, cv::Scalar(0));
  cv::ellipse(m, {160 + dx, 40}, {14, 18}, 0, 0, 360, 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(135 + dx, 58, 50, 90), 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(138 + dx, 148, 18, 92), 255, cv::FILLED);
  cv::rectangle(m, cv::Rect(164 + dx, 148, 18, 92), 255, cv::FILLED);
  return m;
}

inline cv::Mat compose(const cv::Mat& bg, const cv::Mat& person, double gain, double noise, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, noise);
  cv::Mat out(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double base = person.at<std::uint8_t>(y, x) ? 60 + 15 * std::sin(x * 0.2) * std::cos(y * 0.1) : bg.at<std::uint8_t>(y, x);
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(gain * base + n(rng));
    }
  return out;
}

inline LumaView view_of(const cv::Mat& m) { return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step), 1}; }

inline std::int64_t differing(const BitMask& a, const cv::Mat& b) {
  std::int64_t n = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) n += a.get(x, y) != (b.at<std::uint8_t>(y, x) != 0);
  return n;
}

}  // namespace spinewatch::test::synthetic

namespace spinewatch::test::synthetic {

// Colour: a YUYV image from a luma image and one chroma (U, V) per pixel
// (CV_8UC2), U and V averaged over each pixel pair as a camera's 4:2:2 does.
struct YuyvImage {
  std::vector<std::uint8_t> bytes;
  LumaView view() const { return {bytes.data(), kW, kH, 2 * kW, 2}; }
};

inline YuyvImage to_yuyv(const cv::Mat& luma, const cv::Mat& chroma) {
  YuyvImage out;
  out.bytes.resize(static_cast<std::size_t>(2 * kW * kH));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; x += 2) {
      std::uint8_t* p = out.bytes.data() + static_cast<std::ptrdiff_t>(y) * 2 * kW + 2 * x;
      const cv::Vec2b a = chroma.at<cv::Vec2b>(y, x), b = chroma.at<cv::Vec2b>(y, x + 1);
      p[0] = luma.at<std::uint8_t>(y, x);
      p[1] = static_cast<std::uint8_t>((a[0] + b[0] + 1) / 2);
      p[2] = luma.at<std::uint8_t>(y, x + 1);
      p[3] = static_cast<std::uint8_t>((a[1] + b[1] + 1) / 2);
    }
  return out;
}

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

inline YuyvImage compose_colour(const cv::Mat& bg, const cv::Mat& person, const cv::Mat& shadow,
                                const ColourScene& scene, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  cv::Mat luma(kH, kW, CV_8U), chroma(kH, kW, CV_8UC2);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool in_person = person.at<std::uint8_t>(y, x) != 0;
      const double k = !in_person && !shadow.empty() && shadow.at<std::uint8_t>(y, x) ? scene.shadow_factor : 1.0;
      const double l = in_person && scene.person_luma >= 0 ? scene.person_luma : k * bg.at<std::uint8_t>(y, x);
      const cv::Vec2b c = in_person ? scene.person_uv : scene.poster.contains({x, y}) ? scene.poster_uv : scene.wall_uv;
      const double ck = in_person ? 1.0 : k;
      luma.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(l + scene.noise * n(rng));
      chroma.at<cv::Vec2b>(y, x) = {cv::saturate_cast<std::uint8_t>(128 + ck * (c[0] - 128) + scene.chroma_noise * n(rng)),
                                    cv::saturate_cast<std::uint8_t>(128 + ck * (c[1] - 128) + scene.chroma_noise * n(rng))};
    }
  return to_yuyv(luma, chroma);
}

}  // namespace spinewatch::test::synthetic
