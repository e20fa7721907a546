#pragma once
// A background built while the subject is in view (no stored background,
// the station started with the worker at the bench). Two sources of
// evidence (docs/tuning.md, "Bootstrapping"):
//   - the subject's movement: over a sliding window of sampled frames, a
//     pixel the subject uncovered shows the scene behind it in some
//     samples;
//   - the scene's own structure: walls and floors are smooth, so the scene
//     inside the region the subject swept is predicted from its
//     surroundings (inpainting), and of each pixel's samples the one that
//     agrees with the prediction is the scene; where none agrees, the
//     subject never uncovered it and the prediction stands in.
// A bootstrap is accepted only when the prediction holds on known scene
// around the region (a smooth wall and floor); until then there is no
// background, and the estimator says so (init, flag no_background)
// instead of guessing.
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/frames/frame.hpp"

namespace spinewatch {

struct BootstrapOptions {
  int threshold = 28;          // grey levels: a change this large is movement / not the scene
  int min_moved_px = 600;      // movement smaller than a person's outline is not enough
  int sample_every = 3;        // frames between samples
  int window_samples = 30;     // samples kept (30 × 3 frames = 3 s at 30 fps)
  int min_samples = 5;         // before the first attempt: a median of at least this many
  // The prediction, tried on known scene around the region, may be off by
  // at most this fraction of the threshold (90th percentile): else the
  // scene has too much structure to be predicted, and there is no
  // bootstrap until a background is stored.
  double max_holdout_error = 0.5;
  // ... and at most this fraction of it may be off by more than the
  // threshold (a part of the subject reaching out of the region).
  double max_holdout_outliers = 0.005;
};

struct BootstrapAttempt {
  int samples = 0;
  std::int64_t moved_px = 0;     // pixels whose samples changed by more than the threshold
  std::int64_t swept_px = 0;     // the region the subject covered at some time (holes filled)
  std::int64_t revealed_px = 0;  // of those, pixels seen showing the predicted scene
  double holdout_p90 = 0;        // grey levels: the prediction's error on held-out scene
  double holdout_outliers = 0;   // fraction of the held-out scene off by more than the threshold
  double revealed() const { return swept_px > 0 ? double(revealed_px) / double(swept_px) : 0.0; }
};

class BackgroundBootstrap {
 public:
  explicit BackgroundBootstrap(BootstrapOptions options = {});

  // Where the subject can be in this view (the station's calibrated
  // place, silhouette/person_prior.hpp): inside it, the scene is predicted
  // from around it even where the subject never moved. Empty: only the
  // region the movement outlines.
  void set_prior(const BitMask& region);

  // Every frame while there is no background; true when this frame was
  // sampled (an attempt then has new evidence).
  bool add(const LumaView& frame);
  // Pixels that changed over the samples so far (opened: noise removed).
  std::int64_t moved_px() const;
  // Whether an image of the scene (a learnt mean) holds someone: the
  // largest blob inside the prior that differs from what its surroundings
  // predict, in pixels (0 without a prior).
  std::int64_t occupied_px(const std::vector<std::uint8_t>& image) const;
  // The per-pixel median of the samples so far (width × height bytes): the
  // empty scene when nothing moved (`spinewatch background`).
  std::vector<std::uint8_t> median() const;
  int samples() const { return static_cast<int>(samples_.size()); }
  // Tries to build the background from the samples so far: the image
  // (width × height bytes) when accepted, nothing otherwise; last_attempt()
  // tells why.
  std::optional<std::vector<std::uint8_t>> attempt();
  const BootstrapAttempt& last_attempt() const { return last_; }
  void reset();

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  BootstrapOptions options_;
  int width_ = 0, height_ = 0;
  std::uint64_t frames_ = 0;
  std::vector<std::vector<std::uint8_t>> samples_;  // ring, oldest at next_
  std::size_t next_ = 0;
  BootstrapAttempt last_;
  BitMask prior_;
  cv::Mat prior_mat() const;
};

}  // namespace spinewatch
