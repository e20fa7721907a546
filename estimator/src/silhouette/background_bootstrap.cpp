// Bootstrapping runs only while a station has no background, every few
// frames, so it is written for clarity with OpenCV rather than for speed
// (a few milliseconds an attempt; docs/performance.md).
#include "spinewatch/estimator/silhouette/background_bootstrap.hpp"

#include <algorithm>
#include <array>

#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

namespace spinewatch {
namespace {

struct SampleStats {
  cv::Mat median, low, high;  // CV_8U per pixel over the samples
};

SampleStats sample_stats(const std::vector<std::vector<std::uint8_t>>& samples, int width, int height) {
  SampleStats s{cv::Mat(height, width, CV_8U), cv::Mat(height, width, CV_8U), cv::Mat(height, width, CV_8U)};
  std::vector<std::uint8_t> values(samples.size());
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < samples.size(); ++k) values[k] = samples[k][i];
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    s.median.data[i] = *mid;
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    s.low.data[i] = *lo;
    s.high.data[i] = *hi;
  }
  return s;
}

// Pixels whose samples spread over more than the threshold, without the
// isolated pixels that noise alone makes.
cv::Mat moved_mask(const SampleStats& s, int threshold) {
  cv::Mat moved = (s.high - s.low) > threshold;
  cv::morphologyEx(moved, moved, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  return moved;
}

// The region the subject covered at some time: the movement closed into a
// shape, its holes filled (the never-moving core of the body is inside it).
cv::Mat swept_region(const cv::Mat& moved) {
  cv::Mat swept;
  cv::morphologyEx(moved, swept, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, {15, 15}));
  // Holes: what the image border cannot reach through unswept pixels.
  cv::Mat outside;
  cv::copyMakeBorder(swept, outside, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  cv::floodFill(outside, cv::Point(0, 0), 255);
  cv::Mat reached = outside(cv::Rect(1, 1, swept.cols, swept.rows)) & ~swept;
  swept = ~reached;
  cv::dilate(swept, swept, cv::getStructuringElement(cv::MORPH_ELLIPSE, {5, 5}));
  return swept;
}

// Held out around the region: about the distance the prediction reaches
// into it from its side.
constexpr int kHoldOutPx = 24;

// The 90th percentile of |a − b| over `where`.
double p90_difference(const cv::Mat& a, const cv::Mat& b, const cv::Mat& where) {
  std::array<int, 256> hist{};
  int n = 0;
  for (int i = 0; i < a.rows * a.cols; ++i)
    if (where.data[i]) {
      ++hist[static_cast<std::size_t>(std::abs(a.data[i] - b.data[i]))];
      ++n;
    }
  int acc = 0;
  for (int d = 0; d < 256; ++d) {
    acc += hist[static_cast<std::size_t>(d)];
    if (10 * acc >= 9 * n) return d;
  }
  return 255;
}

}  // namespace

BackgroundBootstrap::BackgroundBootstrap(BootstrapOptions options) : options_(options) {}

void BackgroundBootstrap::set_prior(const BitMask& region) { prior_ = region; }

void BackgroundBootstrap::reset() {
  samples_.clear();
  next_ = 0;
  frames_ = 0;
  last_ = {};
}

bool BackgroundBootstrap::add(const LumaView& frame) {
  if (width_ == 0) {
    width_ = frame.width;
    height_ = frame.height;
  }
  if (frame.width != width_ || frame.height != height_) return false;
  if (frames_++ % static_cast<std::uint64_t>(std::max(1, options_.sample_every)) != 0) return false;
  std::vector<std::uint8_t> sample(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) sample[static_cast<std::size_t>(y * width_ + x)] = frame.at(x, y);
  const std::size_t window = static_cast<std::size_t>(std::max(3, options_.window_samples));
  if (samples_.size() < window) {
    samples_.push_back(std::move(sample));
  } else {
    samples_[next_] = std::move(sample);
    next_ = (next_ + 1) % window;
  }
  return true;
}

std::int64_t BackgroundBootstrap::moved_px() const {
  if (samples_.size() < 2) return 0;
  return cv::countNonZero(moved_mask(sample_stats(samples_, width_, height_), options_.threshold));
}

std::int64_t BackgroundBootstrap::occupied_px(const std::vector<std::uint8_t>& image) const {
  if (prior_.empty() || prior_.width() != width_ || prior_.height() != height_ ||
      image.size() != static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_))
    return 0;
  const cv::Mat scene(height_, width_, CV_8U, const_cast<std::uint8_t*>(image.data()));
  const cv::Mat region = prior_mat();
  cv::Mat predicted;
  cv::inpaint(scene, region, predicted, 5, cv::INPAINT_TELEA);
  cv::Mat difference;
  cv::absdiff(scene, predicted, difference);
  cv::Mat differs = (difference > options_.threshold) & region;
  cv::morphologyEx(differs, differs, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(differs, labels, stats, centroids, 8);
  std::int64_t largest = 0;
  for (int i = 1; i < n; ++i) largest = std::max<std::int64_t>(largest, stats.at<int>(i, cv::CC_STAT_AREA));
  return largest;
}

cv::Mat BackgroundBootstrap::prior_mat() const {
  cv::Mat region(height_, width_, CV_8U, cv::Scalar(0));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if (prior_.get(x, y)) region.at<std::uint8_t>(y, x) = 255;
  return region;
}

std::vector<std::uint8_t> BackgroundBootstrap::median() const {
  if (samples_.empty()) return {};
  const cv::Mat m = sample_stats(samples_, width_, height_).median;
  return {m.datastart, m.dataend};
}

std::optional<std::vector<std::uint8_t>> BackgroundBootstrap::attempt() {
  last_ = {};
  last_.samples = static_cast<int>(samples_.size());
  if (samples_.size() < static_cast<std::size_t>(std::max(3, options_.min_samples))) return std::nullopt;
  const SampleStats stats = sample_stats(samples_, width_, height_);
  const cv::Mat moved = moved_mask(stats, options_.threshold);
  last_.moved_px = cv::countNonZero(moved);
  const bool has_prior = !prior_.empty() && prior_.width() == width_ && prior_.height() == height_;
  // Without a prior, only movement outlines where the subject is.
  if (!has_prior && last_.moved_px < options_.min_moved_px) return std::nullopt;
  cv::Mat swept = swept_region(moved);
  if (has_prior) swept |= prior_mat();
  last_.swept_px = cv::countNonZero(swept);

  // Is the scene smooth enough to be predicted? The same prediction over
  // a band of known scene around the region, held out, says how far off
  // it is there: a wall or a floor passes, shelves and posters do not.
  cv::Mat band;
  cv::dilate(swept, band, cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * kHoldOutPx + 1, 2 * kHoldOutPx + 1}));
  band &= ~swept;
  cv::Mat held_out;
  cv::inpaint(stats.median, swept | band, held_out, 5, cv::INPAINT_TELEA);
  last_.holdout_p90 = p90_difference(stats.median, held_out, band);
  if (last_.holdout_p90 > options_.max_holdout_error * options_.threshold) return std::nullopt;
  // A part of the subject outside the region (a knee, a hand on the
  // bench) shows in the band as pixels far off the prediction, however
  // smooth the rest is: then the region does not hold the subject.
  cv::Mat band_error;
  cv::absdiff(stats.median, held_out, band_error);
  last_.holdout_outliers = static_cast<double>(cv::countNonZero((band_error > options_.threshold) & band)) /
                           std::max(1, cv::countNonZero(band));
  if (last_.holdout_outliers > options_.max_holdout_outliers) return std::nullopt;

  // The scene inside the swept region as its surroundings predict it.
  cv::Mat predicted;
  cv::inpaint(stats.median, swept, predicted, 5, cv::INPAINT_TELEA);

  std::vector<std::uint8_t> image(stats.median.datastart, stats.median.dataend);
  const std::size_t n = image.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (swept.data[i] == 0) continue;
    const int p = predicted.data[i];
    // Of this pixel's samples, the one nearest the prediction: the scene,
    // when the subject ever uncovered the pixel.
    int best = stats.median.data[i];
    for (const auto& sample : samples_)
      if (std::abs(sample[i] - p) < std::abs(best - p)) best = sample[i];
    if (std::abs(best - p) <= options_.threshold) {
      image[i] = static_cast<std::uint8_t>(best);
      ++last_.revealed_px;
    } else {
      image[i] = static_cast<std::uint8_t>(p);
    }
  }
  return image;
}

}  // namespace spinewatch
