#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include <spdlog/spdlog.h>

#include "silhouette/scene_edges.hpp"
#include "silhouette/threshold_row.hpp"
#include "spinewatch/estimator/silhouette/silhouette.hpp"
#include "spinewatch/frames/printable.hpp"

namespace spinewatch {

Result<BackgroundMode> parse_background_mode(std::string_view text) {
  if (text == "learn") return BackgroundMode::Learn;
  if (text == "image") return BackgroundMode::Image;
  if (text == "threshold") return BackgroundMode::Threshold;
  return Error{"silhouette.background: \"" + printable(text) + "\" is not one of learn, image, threshold"};
}

std::string_view to_string(BackgroundMode mode) {
  switch (mode) {
    case BackgroundMode::Learn: return "learn";
    case BackgroundMode::Image: return "image";
    case BackgroundMode::Threshold: return "threshold";
  }
  return "?";
}

std::string_view to_string(SilhouetteStatus status) {
  switch (status) {
    case SilhouetteStatus::LearningBackground: return "learning_background";
    case SilhouetteStatus::NoBackground: return "no_background";
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

SilhouetteExtractor::SilhouetteExtractor(SilhouetteOptions options)
    : options_(options), model_([&] {
        BackgroundAdaptation a = options.adaptation;
        a.learn_frames = options.learn_frames;
        return a;
      }()),
      bootstrap_([&] {
        BootstrapOptions b = options.bootstrapping;
        b.threshold = options.threshold;
        return b;
      }()) {}

bool SilhouetteExtractor::background_ready() const {
  return model_.ready() || options_.background == BackgroundMode::Threshold;
}

bool SilhouetteExtractor::relearn_background() {
  if (options_.background != BackgroundMode::Learn) return false;
  model_.clear();
  bootstrapping_ = false;
  bootstrap_.reset();
  person_ = BitMask{};
  return true;
}

Status SilhouetteExtractor::set_background(const LumaView& bg) {
  if (bg.data == nullptr || bg.width <= 0 || bg.height <= 0)
    return Error{"silhouette background: empty image"};
  if (width_ != 0 && (bg.width != width_ || bg.height != height_))
    return Error{"silhouette background: " + std::to_string(bg.width) + "x" + std::to_string(bg.height) +
                 " does not match the frames' " + std::to_string(width_) + "x" + std::to_string(height_)};
  width_ = bg.width;
  height_ = bg.height;
  if (auto s = model_.set(bg, BackgroundSource::Stored); !s) return Error{"silhouette background: " + s.error().message};
  bootstrapping_ = false;
  bootstrap_.reset();
  return Ok{};
}

// No background yet. Learn mode averages the first frames; when those
// frames moved (the subject was in view), the mean would hold the subject,
// so the station bootstraps instead and says no_background until it can.
SilhouetteStatus SilhouetteExtractor::start_background(const LumaView& frame) {
  if (options_.background != BackgroundMode::Learn) return SilhouetteStatus::NoBackground;  // image: not given
  if (!bootstrapping_) {
    if (options_.bootstrap) bootstrap_.add(frame);
    if (!model_.learn(frame)) return SilhouetteStatus::LearningBackground;
    if (!options_.bootstrap) return SilhouetteStatus::LearningBackground;
    // The mean stands when the frames were still and it holds nobody at
    // the subject's place (a person standing still is not movement, but
    // it is not the smooth scene around them either).
    const std::int64_t moved = bootstrap_.moved_px();
    const std::int64_t occupied = bootstrap_.occupied_px(model_.pixels());
    spdlog::debug("silhouette: learnt background: {} px moved, {} px at the subject's place unlike their surroundings",
                  moved, occupied);
    if (moved < options_.bootstrapping.min_moved_px && occupied < options_.min_blob_px) {
      bootstrap_.reset();
      return SilhouetteStatus::LearningBackground;
    }
    model_.clear();
    bootstrapping_ = true;
    return SilhouetteStatus::NoBackground;
  }
  if (bootstrap_.add(frame)) {
    auto image = bootstrap_.attempt();
    const BootstrapAttempt& a = bootstrap_.last_attempt();
    spdlog::debug(
        "silhouette: bootstrap attempt: {} samples, {} px moved, {} px predicted ({:.0f} % seen uncovered), "
        "prediction off by {} grey levels on held-out scene, {:.1f} % of it beyond the threshold{}",
        a.samples, a.moved_px, a.swept_px, 100 * a.revealed(), a.holdout_p90, 100 * a.holdout_outliers,
        image ? ": accepted" : "");
    if (image) {
      const LumaView view{image->data(), width_, height_, width_, 1};
      if (model_.set(view, BackgroundSource::Bootstrapped)) {
        bootstrapping_ = false;
        bootstrap_.reset();
      }
    }
  }
  return SilhouetteStatus::NoBackground;
}

namespace {
// ⌈2^24 / b⌉: n / b for n < 2^16 as (n · ⌈2^24 / b⌉) >> 24, exact (the
// rounding up adds under 2^16 / 2^24 = 1/256 ≤ 1/b) and free of the divider
// that made the gain estimate cost more than the threshold of a frame.
constexpr std::array<std::uint32_t, 256> kReciprocal = [] {
  std::array<std::uint32_t, 256> r{};
  for (std::uint32_t b = 1; b < 256; ++b) r[b] = ((1U << 24) + b - 1) / b;
  return r;
}();
}  // namespace

// Exposure flicker scales the whole frame; the median of frame/background
// over a sparse grid is that scale as long as the person covers less than
// half of the grid (a standing person covers about a fifth of a view).
double SilhouetteExtractor::estimate_gain(const LumaView& frame) const {
  constexpr int kBins = 256;  // ratio 0.5 … 1.5 in steps of 1/256
  // Nearly every sample lands in the same bin; four histograms in turn keep
  // the increments from waiting on each other.
  std::array<std::array<int, kBins>, 4> hist{};
  int samples = 0;
  for (int y = 4; y < height_; y += 8) {
    const std::uint8_t* row = frame.row(y);
    const std::uint8_t* bg = model_.row(y);
    for (int x = 4; x < width_; x += 8) {
      const int b = bg[x];
      if (b < 16) continue;  // too dark for a ratio
      const int bin = static_cast<int>((std::uint64_t{row[x * frame.step]} * 256 * kReciprocal[static_cast<std::size_t>(b)]) >> 24) - 128;
      ++hist[static_cast<std::size_t>(samples & 3)][static_cast<std::size_t>(std::clamp(bin, 0, kBins - 1))];
      ++samples;
    }
  }
  if (samples == 0) return 1.0;
  int acc = 0;
  for (int i = 0; i < kBins; ++i) {
    const auto bin = static_cast<std::size_t>(i);
    acc += hist[0][bin] + hist[1][bin] + hist[2][bin] + hist[3][bin];
    if (2 * acc >= samples) return (i + 128.5) / 256.0;
  }
  return 1.0;
}

namespace {
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
  if (options_.background == BackgroundMode::Threshold) {
    // The paper's plain threshold against a uniform backdrop (not the hot path).
    const int level = backdrop_level(frame);
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x)
        if (std::abs(frame.at(x, y) - level) > options_.threshold) out.set(x, y);
    return;
  }
  silhouette_detail::ThresholdRow row;
  row.frame_step = frame.step;
  row.width = width_;
  row.gain_q7 = silhouette_detail::gain_to_q7(gain);
  row.threshold = options_.threshold;
  row.chroma_threshold = options_.chroma_threshold;
  row.shadow_q7 = silhouette_detail::ratio_to_q7(options_.shadow_ratio);
  const bool with_chroma = colour(frame);
  for (int y = 0; y < height_; ++y) {
    row.frame = frame.row(y);
    row.background = model_.row(y);
    row.chroma_background = with_chroma ? model_.chroma_row(y) : nullptr;
    silhouette_detail::threshold_row(row, out.row(y));
  }
}

bool SilhouetteExtractor::colour(const LumaView& frame) const {
  return frame.step == 2 && model_.has_chroma() && options_.chroma_threshold > 0 && width_ % 2 == 0;
}

// The same per-pixel test at half the threshold, luma alone, less the
// person's blob, opened (SilhouetteResult::unseen).
void SilhouetteExtractor::find_unseen(const LumaView& frame, SilhouetteResult& result) const {
  if (colour(frame)) return;
  result.unseen = BitMask(width_, height_);
  silhouette_detail::ThresholdRow row;
  row.frame_step = frame.step;
  row.width = width_;
  row.gain_q7 = silhouette_detail::gain_to_q7(result.gain);
  row.threshold = options_.threshold / 2;
  for (int y = 0; y < height_; ++y) {
    row.frame = frame.row(y);
    row.background = model_.row(y);
    std::uint64_t* out = result.unseen.row(y);
    silhouette_detail::threshold_row(row, out);
    const std::uint64_t* person = result.mask.row(y);
    for (int w = 0; w < result.unseen.words_per_row(); ++w) out[w] &= ~person[w];
  }
  open_square(result.unseen, 1);
}

SilhouetteResult SilhouetteExtractor::extract(const LumaView& frame, const BitMask* gate) {
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
    result.status = start_background(frame);
    return result;
  }
  const bool modelled = options_.background != BackgroundMode::Threshold;
  if (modelled) result.gain = estimate_gain(frame);
  threshold_to_bits(frame, result.gain, result.mask);
  close_cross(result.mask);
  if (modelled) foreground_ = result.mask;  // before the blob selection: every blob
  if (gate != nullptr && gate->width() == width_ && gate->height() == height_)
    for (int y = 0; y < height_; ++y) {
      std::uint64_t* row = result.mask.row(y);
      const std::uint64_t* keep = gate->row(y);
      for (int w = 0; w < result.mask.words_per_row(); ++w) row[w] &= keep[w];
    }
  const BlobSummary blobs = keep_largest_blob(result.mask, options_.min_blob_px);
  result.blobs = blobs.blobs;
  result.second_blob_px = blobs.second_px;
  if (blobs.largest_px < options_.min_blob_px) {
    result.mask.clear();
    result.status = SilhouetteStatus::NoPerson;
  } else {
    result.pixels = blobs.largest_px;
    // A second blob that keeps still is scenery the stored background
    // does not hold (a moved chair), not a rival for the person's blob
    // (still_scenery.hpp); one that moves may be another person.
    const bool second_blob =
        blobs.second_px >= options_.min_blob_px &&
        static_cast<double>(blobs.second_px) >= options_.second_blob_fraction * static_cast<double>(blobs.largest_px);
    const bool beside_still = modelled && beside_person_still(result.mask);
    if (second_blob && !beside_still)
      result.status = SilhouetteStatus::TwoBlobs;
    else if (blobs.x_min == 0 || blobs.x_max == width_ - 1)
      result.status = SilhouetteStatus::Occluded;
    else
      result.status = SilhouetteStatus::Person;
  }
  if (modelled && result.status != SilhouetteStatus::NoPerson) {
    find_unseen(frame, result);
    silhouette_detail::mark_scene_edges(result.mask, model_, silhouette_detail::kSceneEdgeGradient, result.scene_edge);
  }
  if (modelled) {
    person_ = result.mask;
    gain_ = result.gain;
  }
  return result;
}

// This frame's foreground outside the person's blob kept still
// (StillScenery), from the foreground before the gate: while tracking, the
// gate cuts a blob away from the person's, and a blob that comes and goes
// with the gate would not look still. And the person's blob is the one it
// was on the last frame (half of it in the same place): two people of
// about one size, one standing still, trade places as the largest blob,
// and whichever is not the largest must not pass for scenery.
bool SilhouetteExtractor::beside_person_still(const BitMask& person) {
  BitMask& other = beside_;
  other = foreground_;  // the same size every frame: no allocation after the first
  std::int64_t person_kept = 0;
  const bool had_person = person_.width() == width_ && person_.height() == height_;
  for (int y = 0; y < height_; ++y) {
    std::uint64_t* row = other.row(y);
    const std::uint64_t* p = person.row(y);
    for (int w = 0; w < other.words_per_row(); ++w) {
      row[w] &= ~p[w];
      if (had_person) person_kept += std::popcount(p[w] & person_.row(y)[w]);
    }
  }
  const bool still = scenery_.still(other);
  return still && 2 * person_kept >= person.count();
}

void SilhouetteExtractor::adapt(const LumaView& frame, const BitMask* person) {
  if (options_.background == BackgroundMode::Threshold || !model_.ready()) return;
  model_.update(frame, foreground_, person != nullptr ? *person : person_, gain_);
}

}  // namespace spinewatch
