// The synthetic scene's per-pixel builders (synthetic_scene.hpp).
#include "synthetic_scene.hpp"

namespace spinewatch::test::synthetic {
namespace {

// Gaussian sensor noise, drawn by OpenCV's generator seeded from the
// test's: a frame's 77 000 draws through std::normal_distribution and
// std::mt19937 ran at the tests' -O0 under the sanitizers whatever this
// file's level (the linker keeps one copy of a template's instantiation,
// here a test object's), 60 % of a 3 000-frame test's time.
class SensorNoise {
 public:
  SensorNoise(std::mt19937& seed, double sigma) : rng_(seed()), sigma_(sigma) {}
  double operator()() { return rng_.gaussian(sigma_); }

 private:
  cv::RNG rng_;
  double sigma_;
};

}  // namespace

cv::Mat background_image() {
  cv::Mat bg(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(150 + 40 * x / kW + 20 * ((x / 16 + y / 16) % 2));
  return bg;
}

cv::Mat smooth_background() {
  cv::Mat bg(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      bg.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(160 + 30 * x / kW + 15 * y / kH + ((x * 7 + y * 13) % 5));
  return bg;
}

cv::Mat compose(const cv::Mat& bg, const cv::Mat& person, double gain, double noise, std::mt19937& rng) {
  SensorNoise n(rng, noise);
  cv::Mat out(kH, kW, CV_8U);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double base = person.at<std::uint8_t>(y, x) ? 60 + 15 * std::sin(x * 0.2) * std::cos(y * 0.1) : bg.at<std::uint8_t>(y, x);
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(gain * base + n());
    }
  return out;
}

std::int64_t differing(const BitMask& a, const cv::Mat& b) {
  std::int64_t n = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) n += a.get(x, y) != (b.at<std::uint8_t>(y, x) != 0);
  return n;
}

YuyvImage to_yuyv(const cv::Mat& luma, const cv::Mat& chroma) {
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

YuyvImage compose_colour(const cv::Mat& bg, const cv::Mat& person, const cv::Mat& shadow,
                         const ColourScene& scene, std::mt19937& rng) {
  SensorNoise n(rng, 1.0);
  cv::Mat luma(kH, kW, CV_8U), chroma(kH, kW, CV_8UC2);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool in_person = person.at<std::uint8_t>(y, x) != 0;
      const double k = !in_person && !shadow.empty() && shadow.at<std::uint8_t>(y, x) ? scene.shadow_factor : 1.0;
      const double l = in_person && scene.person_luma >= 0 ? scene.person_luma : k * bg.at<std::uint8_t>(y, x);
      const cv::Vec2b c = in_person ? scene.person_uv : scene.poster.contains({x, y}) ? scene.poster_uv : scene.wall_uv;
      const double ck = in_person ? 1.0 : k;
      luma.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(l + scene.noise * n());
      chroma.at<cv::Vec2b>(y, x) = {cv::saturate_cast<std::uint8_t>(128 + ck * (c[0] - 128) + scene.chroma_noise * n()),
                                    cv::saturate_cast<std::uint8_t>(128 + ck * (c[1] - 128) + scene.chroma_noise * n())};
    }
  return to_yuyv(luma, chroma);
}

cv::Mat relit(const cv::Mat& bg, double drop) {
  cv::Mat out(bg.size(), CV_8U);
  for (int y = 0; y < bg.rows; ++y)
    for (int x = 0; x < bg.cols; ++x)
      out.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(bg.at<std::uint8_t>(y, x) * (1.0 - drop * (0.5 + 0.5 * x / (bg.cols - 1.0))));
  return out;
}

cv::Mat window(const cv::Mat& bg, double drop) {
  cv::Mat out(bg.size(), CV_8U);
  for (int y = 0; y < bg.rows; ++y)
    for (int x = 0; x < bg.cols; ++x)
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(bg.at<std::uint8_t>(y, x) * (1.0 - drop * x / (bg.cols - 1.0)));
  return out;
}

}  // namespace spinewatch::test::synthetic
