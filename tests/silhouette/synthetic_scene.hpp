#pragma once
// A synthetic scene for the silhouette tests: a textured wall, a
// person-like shape darker than it, sensor noise and exposure gain.
#include <cmath>
#include <cstdint>
#include <random>

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
