#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>

#include "spinewatch/estimator/silhouette/silhouette.hpp"

namespace spinewatch {

Result<BackgroundMode> parse_background_mode(std::string_view text) {
  if (text == "learn") return BackgroundMode::Learn;
  if (text == "image") return BackgroundMode::Image;
  if (text == "threshold") return BackgroundMode::Threshold;
  return Error{"silhouette.background: \"" + std::string(text) + "\" is not one of learn, image, threshold"};
}

std::string_view to_string(SilhouetteStatus status) {
  switch (status) {
    case SilhouetteStatus::LearningBackground: return "learning_background";
    case SilhouetteStatus::NoPerson: return "no_person";
    case SilhouetteStatus::Person: return "person";
    case SilhouetteStatus::TwoBlobs: return "two_blobs";
    case SilhouetteStatus::Occluded: return "occluded";
  }
  return "unknown";
}

std::string_view flag_of(SilhouetteStatus status) {
  return status == SilhouetteStatus::Person ? std::string_view{} : to_string(status);
}

SilhouetteExtractor::SilhouetteExtractor(SilhouetteOptions options) : options_(options) {}

bool SilhouetteExtractor::background_ready() const {
  return ready_ || options_.background == BackgroundMode::Threshold;
}

Status SilhouetteExtractor::set_background(const LumaView& bg) {
  if (bg.data == nullptr || bg.width <= 0 || bg.height <= 0)
    return Error{"silhouette background: empty image"};
  if (width_ != 0 && (bg.width != width_ || bg.height != height_))
    return Error{"silhouette background: " + std::to_string(bg.width) + "x" + std::to_string(bg.height) +
                 " does not match the frames' " + std::to_string(width_) + "x" + std::to_string(height_)};
  width_ = bg.width;
  height_ = bg.height;
  background_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) background_[static_cast<std::size_t>(y * width_ + x)] = bg.at(x, y);
  ready_ = true;
  return Ok{};
}

void SilhouetteExtractor::learn(const LumaView& frame) {
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (learn_sum_.size() != n) learn_sum_.assign(n, 0);
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* row = frame.row(y);
    std::uint32_t* sum = learn_sum_.data() + static_cast<std::ptrdiff_t>(y) * width_;
    for (int x = 0; x < width_; ++x) sum[x] += row[x * frame.step];
  }
  if (++learned_ < std::max(1, options_.learn_frames)) return;
  background_.resize(n);
  const std::uint32_t half = static_cast<std::uint32_t>(learned_ / 2);
  for (std::size_t i = 0; i < n; ++i)
    background_[i] = static_cast<std::uint8_t>((learn_sum_[i] + half) / static_cast<std::uint32_t>(learned_));
  learn_sum_.clear();
  learn_sum_.shrink_to_fit();
  ready_ = true;
}

// Exposure flicker scales the whole frame; the median of frame/background
// over a sparse grid is that scale as long as the person covers less than
// half of the grid (a standing person covers about a fifth of a view).
double SilhouetteExtractor::estimate_gain(const LumaView& frame) const {
  constexpr int kBins = 256;  // ratio 0.5 … 1.5 in steps of 1/256
  std::array<int, kBins> hist{};
  int samples = 0;
  for (int y = 4; y < height_; y += 8) {
    const std::uint8_t* row = frame.row(y);
    const std::uint8_t* bg = background_.data() + static_cast<std::ptrdiff_t>(y) * width_;
    for (int x = 4; x < width_; x += 8) {
      const int b = bg[x];
      if (b < 16) continue;  // too dark for a ratio
      const int bin = (row[x * frame.step] * 256) / b - 128;
      ++hist[static_cast<std::size_t>(std::clamp(bin, 0, kBins - 1))];
      ++samples;
    }
  }
  if (samples == 0) return 1.0;
  int acc = 0;
  for (int i = 0; i < kBins; ++i) {
    acc += hist[static_cast<std::size_t>(i)];
    if (2 * acc >= samples) return (i + 128.5) / 256.0;
  }
  return 1.0;
}

namespace {
// Packs eight 0/1 bytes into eight bits, byte i → bit i (no carries: every
// partial product lands on its own bit).
inline std::uint64_t pack8(const std::uint8_t* flags) {
  std::uint64_t v;
  std::memcpy(&v, flags, 8);
  return (v * 0x0102040810204080ULL) >> 56;
}

// Median grey level of a sparse grid: the backdrop level for the plain threshold.
int backdrop_level(const LumaView& frame) {
  std::array<int, 256> hist{};
  int n = 0;
  for (int y = 2; y < frame.height; y += 4)
    for (int x = 2; x < frame.width; x += 4, ++n) ++hist[frame.at(x, y)];
  int acc = 0;
  for (int i = 0; i < 256; ++i) {
    acc += hist[static_cast<std::size_t>(i)];
    if (2 * acc >= n) return i;
  }
  return 128;
}
}  // namespace

void SilhouetteExtractor::threshold_to_bits(const LumaView& frame, double gain, BitMask& out) const {
  const int words = out.words_per_row();
  std::vector<std::uint8_t> flags(static_cast<std::size_t>(words) * 64, 0);
  const bool plain = options_.background == BackgroundMode::Threshold;
  const int level = plain ? backdrop_level(frame) : 0;
  const int g = static_cast<int>(std::lround(gain * 256.0));   // Q8 gain
  const int t = options_.threshold * 256;
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* row = frame.row(y);
    const std::uint8_t* bg = plain ? nullptr : background_.data() + static_cast<std::ptrdiff_t>(y) * width_;
    const int step = frame.step;
    if (plain) {
      for (int x = 0; x < width_; ++x) flags[static_cast<std::size_t>(x)] = std::abs(row[x * step] - level) > options_.threshold;
    } else if (step == 1) {
      for (int x = 0; x < width_; ++x) flags[static_cast<std::size_t>(x)] = std::abs(row[x] * 256 - g * bg[x]) > t;
    } else {
      for (int x = 0; x < width_; ++x) flags[static_cast<std::size_t>(x)] = std::abs(row[x * step] * 256 - g * bg[x]) > t;
    }
    std::uint64_t* dst = out.row(y);
    for (int w = 0; w < words; ++w) {
      std::uint64_t word = 0;
      for (int b = 0; b < 8; ++b) word |= pack8(flags.data() + w * 64 + b * 8) << (8 * b);
      dst[w] = word;
    }
  }
}

SilhouetteResult SilhouetteExtractor::extract(const LumaView& frame) {
  SilhouetteResult result;
  if (width_ == 0) {
    width_ = frame.width;
    height_ = frame.height;
  }
  result.mask = BitMask(width_, height_);
  if (frame.width != width_ || frame.height != height_) {
    result.status = SilhouetteStatus::NoPerson;
    return result;
  }
  if (!background_ready()) {
    if (options_.background == BackgroundMode::Learn) learn(frame);
    result.status = SilhouetteStatus::LearningBackground;
    return result;
  }
  if (options_.background != BackgroundMode::Threshold) result.gain = estimate_gain(frame);
  threshold_to_bits(frame, result.gain, result.mask);
  close_cross(result.mask);
  const BlobSummary blobs = keep_largest_blob(result.mask, options_.min_blob_px);
  result.blobs = blobs.blobs;
  result.second_blob_px = blobs.second_px;
  if (blobs.largest_px < options_.min_blob_px) {
    result.mask.clear();
    result.status = SilhouetteStatus::NoPerson;
    return result;
  }
  result.pixels = blobs.largest_px;
  if (blobs.second_px >= options_.min_blob_px &&
      static_cast<double>(blobs.second_px) >= options_.second_blob_fraction * static_cast<double>(blobs.largest_px))
    result.status = SilhouetteStatus::TwoBlobs;
  else if (blobs.x_min == 0 || blobs.x_max == width_ - 1)
    result.status = SilhouetteStatus::Occluded;
  else
    result.status = SilhouetteStatus::Person;
  return result;
}

}  // namespace spinewatch
