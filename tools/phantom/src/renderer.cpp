#include "spinewatch/phantom/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <opencv2/imgproc.hpp>

#include "backdrop_wall.hpp"

namespace spinewatch::phantom {
namespace {

// fillConvexPoly's fixed-point fraction bits: sub-pixel outlines.
constexpr int kShift = 4;
constexpr double kSubpixel = 1 << kShift;
// The lens: real lenses are not perfectly sharp (compose()).
const cv::Size kLensKernel{3, 3};
constexpr double kLensSigma = 0.7;

cv::Mat random_field(std::mt19937& rng, cv::Size size) {
  cv::Mat field(size, CV_32F);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) field.at<float>(y, x) = u(rng);
  return field;
}

}  // namespace

ViewRenderer::ViewRenderer(const CameraModel& camera, cv::Size size, std::uint32_t seed, int view_index,
                           const RoomSetup& room)
    : camera_(camera) {
  std::seed_seq seq{seed, 1u, std::uint32_t(view_index)};
  std::mt19937 rng(seq);

  const Eigen::Vector3d centre = camera.centre_in_world();
  Eigen::Vector3d axis = camera.R.transpose() * Eigen::Vector3d::UnitZ();
  if (axis.y() != 0) {
    // A camera looking down still faces an upright wall.
    axis.y() = 0;
    axis.normalize();
  }
  const double wall = -centre.dot(axis) + kWallBehindMm;
  cv::Mat scene(size, CV_32F);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const Eigen::Vector3d d = camera.ray_through({u + 0.5, v + 0.5});
      const double t_wall = wall / std::max(d.dot(axis), 1e-6);
      const double t_floor = d.y() < 0 ? -centre.y() / d.y() : INFINITY;
      float value;
      if (t_floor < t_wall) {
        value = float(105 + 25 * std::clamp(t_floor / 5000.0, 0.0, 1.0));  // floor, lighter far away
      } else {
        const Eigen::Vector3d hit = centre + t_wall * d;
        const double across = hit.dot(Eigen::Vector3d::UnitY().cross(axis));
        value = float(180 + 12 * (hit.y() / 1000.0 - 1.0) + 8 * across / 1000.0);  // wall, lit from above
      }
      scene.at<float>(v, u) = value;
    }
  // Fixed texture: large blotches plus fine grain.
  cv::Mat blotches;
  cv::resize(random_field(rng, {12, 9}), blotches, size, 0, 0, cv::INTER_CUBIC);
  cv::Mat grain = random_field(rng, size);
  cv::GaussianBlur(grain, grain, {3, 3}, 0.8);
  scene += 9 * blotches + 7 * grain;
  scene.convertTo(background_, CV_8U);

  cloth_texture_ = random_field(rng, size);
  cv::GaussianBlur(cloth_texture_, cloth_texture_, {5, 5}, 1.0);
  cloth_texture_ *= 10;

  // The scene's colour: a warm wall and a greyer floor, with blotches of
  // their own; the same geometry as the luma above. Drawn last, so that the
  // grey scene and the cloth are what they were before there was colour.
  background_chroma_.create(size, CV_32FC2);
  cv::Mat tint;
  cv::resize(random_field(rng, {8, 6}), tint, size, 0, 0, cv::INTER_CUBIC);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const Eigen::Vector3d d = camera.ray_through({u + 0.5, v + 0.5});
      const double t_wall = wall / std::max(d.dot(axis), 1e-6);
      const double t_floor = d.y() < 0 ? -centre.y() / d.y() : INFINITY;
      const float t = 2.0f * tint.at<float>(v, u);
      background_chroma_.at<cv::Vec2f>(v, u) = t_floor < t_wall ? cv::Vec2f(-4 + t, 6 - t) : cv::Vec2f(-10 + t, 14 + t);
    }
  if (room.empty()) return;
  // The room over the plain scene, drawn from streams of its own: the plain
  // scene, the cloth and the noise stay what they were.
  cv::Mat luma;
  background_.convertTo(luma, CV_32F);
  cv::Mat depth = paint_room(room, camera, seed, view_index, luma, background_chroma_);
  luma.convertTo(background_, CV_8U);
  if (!room.furniture.empty()) {
    furniture_depth_ = std::move(depth);
    furniture_box_ = cv::boundingRect(furniture_depth_ < std::numeric_limits<float>::infinity());
  }
}

cv::Mat ViewRenderer::person_layer(const BodyPose& body) const {
  cv::Mat layer = cv::Mat::zeros(background_.size(), CV_8U);
  struct Projected {
    double depth;
    std::vector<cv::Point2f> points;
    std::uint8_t shade;
  };
  std::vector<Projected> parts;
  parts.reserve(body.solids.size());
  for (const Solid& solid : body.solids) {
    Projected p{0, {}, solid.shade};
    bool visible = true;
    for (const auto& point : solid.points) {
      auto pixel = camera_.project(point);
      if (!pixel) {
        visible = false;  // a part reaching behind the camera is not drawn
        break;
      }
      p.points.emplace_back(float(pixel->x()), float(pixel->y()));
      p.depth += camera_.to_camera(point).z();
    }
    if (!visible || p.points.empty()) continue;
    p.depth /= double(solid.points.size());
    parts.push_back(std::move(p));
  }
  // Painter's order: farthest first.
  std::sort(parts.begin(), parts.end(), [](const Projected& a, const Projected& b) { return a.depth > b.depth; });

  std::vector<cv::Point2f> hull;
  std::vector<cv::Point> fixed;
  // With furniture, the depth of the part drawn at each pixel the
  // furniture covers, to hide what it is in front of (kept from frame to
  // frame, as compose()'s images).
  const bool furniture = !furniture_box_.empty();
  cv::Mat& depth = scratch_.part_depth;
  if (furniture) {
    depth.create(furniture_box_.size(), CV_32F);
    depth.setTo(std::numeric_limits<float>::infinity());
  }
  const cv::Point box_offset(-furniture_box_.x * int(kSubpixel), -furniture_box_.y * int(kSubpixel));
  for (const Projected& p : parts) {
    cv::convexHull(p.points, hull);
    if (furniture && (cv::boundingRect(hull) & furniture_box_).area() > 0) {
      fixed.clear();
      for (const auto& h : hull) fixed.emplace_back(cvRound(h.x * kSubpixel) + box_offset.x, cvRound(h.y * kSubpixel) + box_offset.y);
      cv::fillConvexPoly(depth, fixed, cv::Scalar(p.depth), cv::LINE_8, kShift);
    }
    cv::Point2f mean(0, 0);
    for (const auto& h : hull) mean += h;
    mean *= 1.0f / float(hull.size());
    // The body part, then a lighter core offset toward the light (above):
    // mild shading so a part is not a flat fill.
    for (auto [scale, lift, extra] : {std::tuple{1.0f, 0.0f, 0}, std::tuple{0.55f, 0.12f, kCoreLift}}) {
      fixed.clear();
      for (const auto& h : hull) {
        const cv::Point2f q = mean + scale * (h - mean) - cv::Point2f(0, lift * std::abs(h.y - mean.y));
        fixed.emplace_back(cvRound(q.x * kSubpixel), cvRound(q.y * kSubpixel));
      }
      cv::fillConvexPoly(layer, fixed, cv::Scalar(std::min(255, p.shade + extra)), cv::LINE_8, kShift);
    }
  }
  if (furniture)
    for (int y = 0; y < depth.rows; ++y) {
      const float* part = depth.ptr<float>(y);
      const float* room = furniture_depth_.ptr<float>(y + furniture_box_.y) + furniture_box_.x;
      std::uint8_t* out = layer.ptr<std::uint8_t>(y + furniture_box_.y) + furniture_box_.x;
      for (int x = 0; x < depth.cols; ++x)
        if (room[x] < part[x]) out[x] = 0;
    }
  return layer;
}

cv::Mat ViewRenderer::shadow_factor(const cv::Mat& mask) const {
  // A soft shadow cast down and to the side onto the wall and floor.
  cv::Mat cast;
  mask.convertTo(cast, CV_32F, 1.0 / 255);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 7, 0, 1, 5);
  cv::warpAffine(cast, cast, shift, cast.size());
  cv::GaussianBlur(cast, cast, {0, 0}, 6.0);
  return 1.0f - 0.35f * cast;
}

cv::Mat ViewRenderer::compose(const cv::Mat& layer, bool shadow, bool camouflage) const {
  Scratch& s = scratch_;
  cv::Mat mask = layer > 0;
  cv::Mat& background = s.background;
  background_.convertTo(background, CV_32F);
  const cv::Mat wall = camouflage ? background.clone() : cv::Mat();
  if (shadow) background = background.mul(shadow_factor(mask));
  // Blur the shades within the person only (normalised by the blurred
  // mask), so the shading is soft but the outline stays where it is.
  layer.convertTo(s.blurred, CV_32F);
  cv::GaussianBlur(s.blurred, s.shade, {7, 7}, 1.5);
  mask.convertTo(s.blurred, CV_32F, 1.0 / 255);
  cv::GaussianBlur(s.blurred, s.weight, {7, 7}, 1.5);
  // shade / max(weight, 10⁻³) + cloth texture, one operation at a time.
  cv::max(s.weight, 1e-3, s.weight);
  cv::divide(s.shade, s.weight, s.person);
  cv::add(s.person, cloth_texture_, s.person);
  if (camouflage) {
    // The clothing at the wall's own brightness, with a little cloth
    // texture; the skin keeps its shade.
    const cv::Mat clothing = mask & (layer != kSkinShade) & (layer != kSkinShade + kCoreLift);
    cv::Mat matched = wall + 0.4f * cloth_texture_;
    matched.copyTo(s.person, clothing);
  }
  s.person.copyTo(background, mask);
  // The lens softens the person's outline a little (the outline is drawn
  // exact). Only within one pixel of the person: the room, shadowed or
  // not, stays the stored background's pixels, as in the empty frames.
  // (The whole frame blurred, every edge of a cluttered room moved when
  // someone walked in and joined the silhouette.)
  cv::GaussianBlur(background, s.blurred, kLensKernel, kLensSigma);
  cv::dilate(mask, s.reach, cv::getStructuringElement(cv::MORPH_RECT, kLensKernel));
  s.blurred.copyTo(background, s.reach);
  cv::Mat out;
  background.convertTo(out, CV_8U);
  return out;
}

namespace {
// The colour of each body part, by its shade in the person layer (the
// part's shade, or the part's lighter core, body.cpp): a blue shirt, navy
// trousers, skin.
std::array<cv::Vec2f, 256> part_chroma() {
  std::array<cv::Vec2f, 256> table{};
  const auto set = [&](int shade, cv::Vec2f c) {
    table[std::size_t(shade)] = c;
    table[std::size_t(std::min(255, shade + kCoreLift))] = c;
  };
  set(kShirtShade, {22, -16});
  set(kSleeveShade, {20, -14});
  set(kTrousersShade, {12, -4});  // navy
  set(kSkinShade, {-14, 18});  // skin
  return table;
}
}  // namespace

cv::Mat ViewRenderer::compose_chroma(const cv::Mat& layer, bool shadow) const {
  static const std::array<cv::Vec2f, 256> kPartChroma = part_chroma();
  cv::Mat mask = layer > 0;
  cv::Mat scene = background_chroma_.clone();
  if (shadow) {
    const cv::Mat factor = shadow_factor(mask);
    for (int y = 0; y < scene.rows; ++y)
      for (int x = 0; x < scene.cols; ++x) scene.at<cv::Vec2f>(y, x) *= factor.at<float>(y, x);
  }
  for (int y = 0; y < scene.rows; ++y)
    for (int x = 0; x < scene.cols; ++x)
      if (const std::uint8_t s = layer.at<std::uint8_t>(y, x); s != 0) scene.at<cv::Vec2f>(y, x) = kPartChroma[s];
  // As compose(): the outline softened, the room as it was.
  cv::Mat blurred, reach;
  cv::GaussianBlur(scene, blurred, kLensKernel, kLensSigma);
  cv::dilate(mask, reach, cv::getStructuringElement(cv::MORPH_RECT, kLensKernel));
  blurred.copyTo(scene, reach);
  return scene;
}

SensorModel::SensorModel(std::uint32_t seed, double noise_sigma, double flicker)
    : seed_(seed), noise_sigma_(noise_sigma), flicker_(flicker), gaussian_(1 << 16) {
  std::seed_seq seq{seed, 3u};
  std::mt19937 rng(seq);
  std::normal_distribution<float> normal(0.f, 1.f);
  for (float& g : gaussian_) g = normal(rng);
}

cv::Mat SensorModel::expose(const cv::Mat& clean, std::uint64_t frame, int view_index) const {
  // One engine per frame and view: any frame can be rendered on its own and
  // still match a whole recording's bytes.
  std::seed_seq seq{seed_, 4u, std::uint32_t(frame), std::uint32_t(frame >> 32), std::uint32_t(view_index)};
  std::mt19937 rng(seq);
  const float gain = float(1.0 + std::uniform_real_distribution<double>(-flicker_, flicker_)(rng));
  // Per-pixel draws come from the table through a xorshift index: an
  // mt19937 draw per pixel would cost more than the whole render.
  std::uint32_t state = rng() | 1u;
  const float sigma = float(noise_sigma_);
  cv::Mat out(clean.size(), CV_8U);
  for (int y = 0; y < clean.rows; ++y) {
    const std::uint8_t* in = clean.ptr<std::uint8_t>(y);
    std::uint8_t* o = out.ptr<std::uint8_t>(y);
    for (int x = 0; x < clean.cols; ++x) {
      state ^= state << 13;
      state ^= state >> 17;
      state ^= state << 5;
      const float v = gain * float(in[x]) + sigma * gaussian_[state >> 16];
      o[x] = cv::saturate_cast<std::uint8_t>(v);
    }
  }
  return out;
}

cv::Mat SensorModel::expose_chroma(const cv::Mat& chroma, std::uint64_t frame, int view_index) const {
  // The same engine as expose(): the same gain; the noise from another
  // stretch of the table.
  std::seed_seq seq{seed_, 4u, std::uint32_t(frame), std::uint32_t(frame >> 32), std::uint32_t(view_index)};
  std::mt19937 rng(seq);
  const float gain = float(1.0 + std::uniform_real_distribution<double>(-flicker_, flicker_)(rng));
  rng();
  std::uint32_t state = rng() | 1u;
  const float sigma = float(noise_sigma_ / 2);
  cv::Mat out(chroma.size(), CV_8UC2);
  for (int y = 0; y < chroma.rows; ++y)
    for (int x = 0; x < chroma.cols; ++x) {
      const cv::Vec2f c = chroma.at<cv::Vec2f>(y, x);
      cv::Vec2b& o = out.at<cv::Vec2b>(y, x);
      for (int k = 0; k < 2; ++k) {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        o[k] = cv::saturate_cast<std::uint8_t>(128.0f + gain * c[k] + sigma * gaussian_[state >> 16]);
      }
    }
  return out;
}

std::vector<std::uint8_t> to_yuyv(const cv::Mat& grey, const cv::Mat& chroma) {
  std::vector<std::uint8_t> out(std::size_t(grey.total()) * 2);
  std::size_t k = 0;
  for (int y = 0; y < grey.rows; ++y) {
    const std::uint8_t* row = grey.ptr<std::uint8_t>(y);
    const cv::Vec2b* c = chroma.ptr<cv::Vec2b>(y);
    for (int x = 0; x + 1 < grey.cols; x += 2, k += 4) {
      out[k] = row[x];
      out[k + 1] = std::uint8_t((c[x][0] + c[x + 1][0] + 1) / 2);
      out[k + 2] = row[x + 1];
      out[k + 3] = std::uint8_t((c[x][1] + c[x + 1][1] + 1) / 2);
    }
  }
  return out;
}

std::vector<std::uint8_t> to_yuyv(const cv::Mat& grey) {
  std::vector<std::uint8_t> out(std::size_t(grey.total()) * 2, 128);
  std::size_t k = 0;
  for (int y = 0; y < grey.rows; ++y) {
    const std::uint8_t* row = grey.ptr<std::uint8_t>(y);
    for (int x = 0; x < grey.cols; ++x, k += 2) out[k] = row[x];
  }
  return out;
}

}  // namespace spinewatch::phantom
