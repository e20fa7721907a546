#include "spinewatch/estimator/silhouette/background_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace spinewatch {
namespace {

// Each frame adapts every kRowPhases-th row, starting one row further down
// than the frame before: every row once in kRowPhases frames, at the rate
// that gives the configured time constant. Light changes over seconds, so
// the half-second lag costs nothing, and a frame pays a sixteenth.
constexpr int kRowPhases = 16;

// The per-update rate in Q12 for a per-frame time constant of `frames`,
// applied once every kRowPhases frames: 1 − (1 − 1/frames)^kRowPhases.
int rate_q12(double frames) {
  if (frames <= 0) return 0;
  const double per_frame = 1.0 / std::max(frames, 1.0);
  const double per_update = 1.0 - std::pow(1.0 - per_frame, kRowPhases);
  return std::clamp(static_cast<int>(std::lround(per_update * 4096.0)), 1, 4096);
}

// Row y of the person grown by `radius` (the square dilation, for one
// row): the OR of the rows within the radius, then spread sideways. The
// adaptation needs a sixteenth of the rows; growing the whole mask would
// cost more than adapting them.
void near_of(const BitMask& person, int y, int radius, std::uint64_t* out, std::uint64_t* before) {
  const int words = person.words_per_row();
  std::fill(out, out + words, 0);
  for (int yy = std::max(0, y - radius); yy <= std::min(person.height() - 1, y + radius); ++yy) {
    const std::uint64_t* row = person.row(yy);
    for (int w = 0; w < words; ++w) out[w] |= row[w];
  }
  const std::uint64_t keep = (person.width() & 63) != 0 ? (std::uint64_t{1} << (person.width() & 63)) - 1 : ~std::uint64_t{0};
  for (int reach = 0; reach < radius;) {
    const int s = std::min({std::max(reach, 1), radius - reach, 63});
    std::copy(out, out + words, before);
    for (int w = 0; w < words; ++w) {
      const std::uint64_t mid = before[w];
      const std::uint64_t prev = w > 0 ? before[w - 1] : 0;
      const std::uint64_t next = w + 1 < words ? before[w + 1] : 0;
      out[w] = mid | (mid << s) | (prev >> (64 - s)) | (mid >> s) | (next << (64 - s));
    }
    out[words - 1] &= keep;
    reach += s;
  }
}

}  // namespace

std::string_view to_string(BackgroundSource source) {
  switch (source) {
    case BackgroundSource::None: return "none";
    case BackgroundSource::Stored: return "stored";
    case BackgroundSource::Learnt: return "learnt";
    case BackgroundSource::Bootstrapped: return "bootstrapped";
  }
  return "unknown";
}

BackgroundModel::BackgroundModel(BackgroundAdaptation options) : options_(options) {}

void BackgroundModel::Plane::set_from(const LumaView& image, int offset) {
  const std::size_t n = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  bytes.resize(n);
  average.resize(n);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* in = image.row(y) + offset;
    for (int x = 0; x < image.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * image.width + x);
      bytes[i] = in[x * image.step];
      average[i] = static_cast<std::uint16_t>(bytes[i] << 8);
    }
  }
}

void BackgroundModel::Plane::accumulate(const LumaView& frame, int offset) {
  const std::size_t n = static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height);
  if (learn_sum.size() != n) learn_sum.assign(n, 0);
  for (int y = 0; y < frame.height; ++y) {
    const std::uint8_t* row = frame.row(y) + offset;
    std::uint32_t* sum = learn_sum.data() + static_cast<std::ptrdiff_t>(y) * frame.width;
    for (int x = 0; x < frame.width; ++x) sum[x] += row[x * frame.step];
  }
}

void BackgroundModel::Plane::finish_learning(std::uint32_t count) {
  const std::size_t n = learn_sum.size();
  bytes.resize(n);
  average.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // The Q8 mean keeps the fraction the byte rounds away.
    const std::uint32_t q8 = (learn_sum[i] * 256 + count / 2) / count;
    average[i] = static_cast<std::uint16_t>(std::min<std::uint32_t>(q8, 0xFFFF));
    bytes[i] = static_cast<std::uint8_t>(std::min<std::uint32_t>((q8 + 128) >> 8, 255));
  }
}

// A camera that sends YUYV but no colour (a monochrome sensor, our own
// grey phantom recordings) has chroma 128 everywhere: the colour test
// would cost a frame's worth of work and decide nothing.
bool BackgroundModel::Plane::has_colour() const {
  return std::any_of(bytes.begin(), bytes.end(), [](std::uint8_t c) { return c < 127 || c > 129; });
}

void BackgroundModel::Plane::clear() {
  bytes.clear();
  average.clear();
  learn_sum.clear();
  learn_sum.shrink_to_fit();
}

Status BackgroundModel::set(const LumaView& image, BackgroundSource source) {
  if (image.data == nullptr || image.width <= 0 || image.height <= 0) return Error{"empty image"};
  if (width_ != 0 && (image.width != width_ || image.height != height_))
    return Error{std::to_string(image.width) + "x" + std::to_string(image.height) + " does not match the frames' " +
                 std::to_string(width_) + "x" + std::to_string(height_)};
  width_ = image.width;
  height_ = image.height;
  luma_.set_from(image, 0);
  if (image.step == 2)
    chroma_.set_from(image, 1);  // YUYV: chroma in the odd bytes
  if (image.step != 2 || !chroma_.has_colour()) chroma_.clear();
  source_ = source;
  if (source == BackgroundSource::Bootstrapped) ++counters_.bootstraps;
  abandon_learning();
  return Ok{};
}

bool BackgroundModel::learn(const LumaView& frame) {
  if (width_ == 0) {
    width_ = frame.width;
    height_ = frame.height;
  }
  if (frame.width != width_ || frame.height != height_) return false;
  if (learned_ == 0) learning_chroma_ = frame.step == 2;
  learning_chroma_ = learning_chroma_ && frame.step == 2;
  luma_.accumulate(frame, 0);
  if (learning_chroma_) chroma_.accumulate(frame, 1);
  if (++learned_ < std::max(1, options_.learn_frames)) return false;
  const std::uint32_t count = static_cast<std::uint32_t>(learned_);
  luma_.finish_learning(count);
  if (learning_chroma_) chroma_.finish_learning(count);
  if (!learning_chroma_ || !chroma_.has_colour()) chroma_.clear();
  if (source_ != BackgroundSource::None) ++counters_.relearns;
  source_ = BackgroundSource::Learnt;
  abandon_learning();
  return true;
}

void BackgroundModel::abandon_learning() {
  for (Plane* p : {&luma_, &chroma_}) {
    p->learn_sum.clear();
    p->learn_sum.shrink_to_fit();
  }
  learned_ = 0;
}

void BackgroundModel::clear() {
  source_ = BackgroundSource::None;
  luma_.clear();
  chroma_.clear();
  abandon_learning();
  empty_frames_ = 0;
}

void BackgroundModel::update(const LumaView& frame, const BitMask& foreground, const BitMask& person, double gain) {
  if (!ready() || frame.width != width_ || frame.height != height_) return;
  const bool empty = person.empty() || person.count() == 0;
  empty_frames_ = empty ? empty_frames_ + 1 : 0;
  if (!empty && learned_ > 0) abandon_learning();  // someone came in: that mean is not an empty scene
  if (options_.relearn_empty_frames > 0 && empty_frames_ >= options_.relearn_empty_frames) {
    if (learn(frame)) empty_frames_ = 0;
    return;  // while re-learning, the running average waits
  }
  if (options_.adapt_frames <= 0) return;
  adapt_rows(frame, foreground, person, gain);
  ++counters_.updates;
}

void BackgroundModel::adapt_rows(const LumaView& frame, const BitMask& foreground, const BitMask& person,
                                 double gain) {
  const int gain_q12 = std::clamp(static_cast<int>(std::lround(gain * 4096.0)), 2048, 8192);
  const int fast = rate_q12(options_.adapt_frames);
  const int slow = rate_q12(options_.adapt_frames * std::max(1.0, options_.foreground_slowdown));
  const bool has_person = !person.empty() && person.width() == width_ && person.height() == height_;
  const bool has_foreground = !foreground.empty() && foreground.width() == width_ && foreground.height() == height_;
  const bool colour = has_chroma() && frame.step == 2;
  const int words = (width_ + 63) / 64;
  near_row_.resize(2 * static_cast<std::size_t>(words));
  const int phase = static_cast<int>(frame_counter_++ % kRowPhases);
  for (int y = phase; y < height_; y += kRowPhases) {
    const std::uint64_t* near = nullptr;
    if (has_person) {
      near_of(person, y, options_.margin_px, near_row_.data(), near_row_.data() + words);
      near = near_row_.data();
    }
    const std::uint64_t* fg = has_foreground ? foreground.row(y) : nullptr;
    adapt_plane(luma_, frame, 0, 0, y, near, fg, gain_q12, fast, slow);
    // Chroma byte x belongs to pixel x's pair: pixel x's masks stand for it.
    if (colour) adapt_plane(chroma_, frame, 1, 128, y, near, fg, gain_q12, fast, slow);
  }
}

void BackgroundModel::adapt_plane(Plane& plane, const LumaView& frame, int offset, int neutral, int y,
                                  const std::uint64_t* near, const std::uint64_t* fg, int gain_q12, int fast,
                                  int slow) {
  const std::uint8_t* in = frame.row(y) + offset;
  const int step = frame.step;
  std::uint16_t* average = plane.average.data() + static_cast<std::ptrdiff_t>(y) * width_;
  std::uint8_t* out = plane.bytes.data() + static_cast<std::ptrdiff_t>(y) * width_;
  const int neutral_q8 = neutral << 8;
  for (int x0 = 0; x0 < width_; x0 += 64) {
    const int x1 = std::min(width_, x0 + 64);
    const std::uint64_t near_bits = near != nullptr ? near[x0 >> 6] : 0;
    const std::uint64_t fg_bits = fg != nullptr ? fg[x0 >> 6] : 0;
    if ((near_bits | fg_bits) == 0) {
      // Most of a frame is plain scene: one rate, no masks, a loop the
      // compiler vectorises.
      for (int x = x0; x < x1; ++x) {
        const int a = average[x];
        const int next = a + (((in[x * step] << 8) - a) * fast + 2048) / 4096;
        average[x] = static_cast<std::uint16_t>(next);
        out[x] = static_cast<std::uint8_t>((next + 128) >> 8);
      }
      continue;
    }
    for (int x = x0; x < x1; ++x) {
      const std::uint64_t bit = std::uint64_t{1} << (x & 63);
      const int a = average[x];
      int target = 0, rate = fast;
      if ((near_bits & bit) != 0) {
        // Under the person and the margin around them the scene is not
        // seen, but the light on it changes as on the rest of the scene:
        // these pixels follow the scene's overall change (the exposure
        // gain, about black for luma and about grey for chroma), so that
        // what the subject uncovers after an hour under a window is not
        // stale.
        target = neutral_q8 + (((a - neutral_q8) * gain_q12 + 2048) >> 12);
      } else {
        // Foreground that is not the person adapts slowly: a passer-by is
        // not learnt, an object left there is, in a minute or two.
        if ((fg_bits & bit) != 0) rate = slow;
        target = in[x * step] << 8;
      }
      // Rounded, not floored: a floor would pull a steady pixel down by
      // up to half a grey level at the slow rate.
      const int next = std::clamp(a + ((target - a) * rate + 2048) / 4096, 0, 0xFFFF);
      average[x] = static_cast<std::uint16_t>(next);
      out[x] = static_cast<std::uint8_t>(std::min(255, (next + 128) >> 8));
    }
  }
}

void dilate_square(const BitMask& in, int radius, BitMask& out) {
  const int words = in.words_per_row();
  const int height = in.height();
  const std::uint64_t keep = (in.width() & 63) != 0 ? (std::uint64_t{1} << (in.width() & 63)) - 1 : ~std::uint64_t{0};
  radius = std::max(radius, 0);
  // Horizontally by shifts of 1, 1, 2, 4, … (each step doubles the reach,
  // the last one tops it up to the radius), then vertically as the OR over
  // the window of rows.
  std::vector<std::uint64_t> grown(static_cast<std::size_t>(words) * static_cast<std::size_t>(height));
  std::vector<std::uint64_t> before(static_cast<std::size_t>(words));
  for (int y = 0; y < height; ++y) {
    std::uint64_t* row = grown.data() + static_cast<std::ptrdiff_t>(y) * words;
    std::copy(in.row(y), in.row(y) + words, row);
    for (int reach = 0; reach < radius;) {
      const int s = std::min({std::max(reach, 1), radius - reach, 63});
      std::copy(row, row + words, before.begin());
      for (int w = 0; w < words; ++w) {
        const std::uint64_t mid = before[static_cast<std::size_t>(w)];
        const std::uint64_t prev = w > 0 ? before[static_cast<std::size_t>(w - 1)] : 0;
        const std::uint64_t next = w + 1 < words ? before[static_cast<std::size_t>(w + 1)] : 0;
        row[w] = mid | (mid << s) | (prev >> (64 - s)) | (mid >> s) | (next << (64 - s));
      }
      row[words - 1] &= keep;
      reach += s;
    }
  }
  // Vertically the same way, in place: rows pulled up from s below
  // (top-down, so each reads a row not yet grown in this pass), then down
  // from s above (bottom-up); each pass reaches s further.
  for (int reach = 0; reach < radius;) {
    const int s = std::min(std::max(reach, 1), radius - reach);
    for (int y = 0; y + s < height; ++y) {
      std::uint64_t* dst = grown.data() + static_cast<std::ptrdiff_t>(y) * words;
      const std::uint64_t* below = dst + static_cast<std::ptrdiff_t>(s) * words;
      for (int w = 0; w < words; ++w) dst[w] |= below[w];
    }
    for (int y = height - 1; y - s >= 0; --y) {
      std::uint64_t* dst = grown.data() + static_cast<std::ptrdiff_t>(y) * words;
      const std::uint64_t* above = dst - static_cast<std::ptrdiff_t>(s) * words;
      for (int w = 0; w < words; ++w) dst[w] |= above[w];
    }
    reach += s;
  }
  for (int y = 0; y < height; ++y)
    std::copy(grown.data() + static_cast<std::ptrdiff_t>(y) * words, grown.data() + static_cast<std::ptrdiff_t>(y + 1) * words,
              out.row(y));
}

}  // namespace spinewatch
