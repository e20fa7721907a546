#pragma once
// The empty scene as one camera sees it, and how it is kept up to date
// over a shift (docs/tuning.md, "Background"):
//   - where it came from: a stored image, learnt from an empty scene, or
//     bootstrapped while the subject was in view (background_bootstrap.hpp);
//   - adaptation: a running average towards each frame outside the person
//     and a margin around them, so slow and uneven light changes (a
//     window, a lamp, exposure) are followed; under the person the
//     background follows the scene's overall change; foreground that is
//     not the person (a moved chair) is absorbed far more slowly;
//   - re-learning: when the scene has been empty for a while, the whole
//     background is replaced by the mean of the next empty frames;
//   - colour: given YUYV (a LumaView of step 2), the model keeps the
//     chroma too, U and V of each pixel pair interleaved as in the frame,
//     learnt and adapted as the luma is (under the person it follows the
//     gain about neutral grey). A background set from grey has none, nor
//     one whose chroma is neutral grey everywhere (a camera without colour).
// Pure computation: the caller reads and writes images.
#include <algorithm>
#include <cstdint>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

enum class BackgroundSource : std::uint8_t {
  None,          // nothing yet
  Stored,        // an image given by the caller (spinewatch background)
  Learnt,        // the mean of frames of an empty scene
  Bootstrapped,  // built from the subject's movement with the subject in view
};
std::string_view to_string(BackgroundSource source);

struct BackgroundAdaptation {
  // Time constant of the running average outside the person, in frames
  // (0: the background never changes once set).
  double adapt_frames = 60;
  // Foreground that is not the person adapts this many times slower, so a
  // passer-by is not learnt but a moved chair is, within a minute or two.
  double foreground_slowdown = 20;
  // The person and this many pixels around them are not learnt from the
  // frame (the blur of the outline and the next frame's movement must not
  // become background); they follow the scene's overall light change.
  int margin_px = 8;
  // An empty scene for this many frames re-learns the whole background
  // (0: never).
  int relearn_empty_frames = 300;
  // Frames averaged for a (re-)learnt background.
  int learn_frames = 10;
};

struct BackgroundCounters {
  std::uint64_t updates = 0;     // frames the background adapted to
  std::uint64_t relearns = 0;    // whole backgrounds re-learnt from an empty scene
  std::uint64_t bootstraps = 0;  // backgrounds built with the subject in view
};

class BackgroundModel {
 public:
  explicit BackgroundModel(BackgroundAdaptation options = {});

  bool ready() const { return source_ != BackgroundSource::None; }
  BackgroundSource source() const { return source_; }
  const BackgroundCounters& counters() const { return counters_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Packed rows of width() bytes; valid once ready().
  const std::uint8_t* row(int y) const { return luma_.bytes.data() + static_cast<std::ptrdiff_t>(y) * width_; }
  const std::vector<std::uint8_t>& pixels() const { return luma_.bytes; }
  // Chroma: rows of width() bytes, U V U V … (one pair per two pixels).
  bool has_chroma() const { return !chroma_.bytes.empty(); }
  const std::uint8_t* chroma_row(int y) const {
    return chroma_.bytes.data() + static_cast<std::ptrdiff_t>(y) * width_;
  }

  // Replaces the whole background (with chroma when `image` is YUYV).
  // Errors name the problem (size).
  Status set(const LumaView& image, BackgroundSource source);

  // Adds an empty-scene frame to the learning mean; true once
  // learn_frames frames are in and the background is set (Learnt).
  bool learn(const LumaView& frame);
  void abandon_learning();
  // Back to no background (the counters stay).
  void clear();

  // One frame after its silhouette: `foreground` is everything that
  // differed from the background, `person` where the subject is (empty
  // when nobody is), `gain` the frame's exposure relative to the
  // background. Adapts a sixteenth of the rows per frame (each row every
  // sixteenth frame at the matching rate: the same time constant at a
  // sixteenth of the cost), and re-learns after an empty spell.
  void update(const LumaView& frame, const BitMask& foreground, const BitMask& person, double gain = 1.0);

 private:
  // One plane of the background: luma (neutral 0) or chroma (neutral 128).
  struct Plane {
    std::vector<std::uint8_t> bytes;      // what the threshold compares with
    std::vector<std::uint16_t> average;   // the same in Q8, for the running average
    std::vector<std::uint32_t> learn_sum; // while learning
    void set_from(const LumaView& frame, int offset);
    void accumulate(const LumaView& frame, int offset);
    void finish_learning(std::uint32_t count);
    bool has_colour() const;  // any chroma off neutral grey
    void clear();
  };
  void adapt_rows(const LumaView& frame, const BitMask& foreground, const BitMask& person, double gain);
  void adapt_plane(Plane& plane, const LumaView& frame, int offset, int neutral, int y, const std::uint64_t* near,
                   const std::uint64_t* fg, int gain_q12, int fast, int slow);

  BackgroundAdaptation options_;
  BackgroundSource source_ = BackgroundSource::None;
  BackgroundCounters counters_;
  int width_ = 0, height_ = 0;
  Plane luma_;
  Plane chroma_;               // empty: no colour
  bool learning_chroma_ = false;  // every frame of this learning mean had colour
  int learned_ = 0;
  int empty_frames_ = 0;
  std::uint64_t frame_counter_ = 0;
  std::vector<std::uint64_t> near_row_;  // scratch: one row of the person grown by the margin, and its copy
};

// The square dilation of `in` by `radius` pixels into `out` (same size).
void dilate_square(const BitMask& in, int radius, BitMask& out);

}  // namespace spinewatch
