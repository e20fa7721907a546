#pragma once
// The person's silhouette in one view: background subtraction with exposure
// compensation, cleaned to the person's blob, packed into a BitMask.
// One extractor per view; it keeps that view's background model
// (background_model.hpp) and, with no background yet, bootstraps one
// (background_bootstrap.hpp).
#include <cstdint>
#include <string_view>
#include <vector>

#include "spinewatch/estimator/silhouette/background_bootstrap.hpp"
#include "spinewatch/estimator/silhouette/background_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/estimator/silhouette/still_scenery.hpp"
#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// Mirrors the [silhouette] keys of the station configuration.
enum class BackgroundMode : std::uint8_t {
  Learn,      // a stored image when given, else the mean of the first
              // learn_frames frames of an empty scene, else bootstrapped
  Image,      // a stored background image given to set_background() only
  Threshold,  // the paper's plain threshold against a uniform backdrop
};
Result<BackgroundMode> parse_background_mode(std::string_view text);
std::string_view to_string(BackgroundMode mode);  // learn | image | threshold

struct SilhouetteOptions {
  BackgroundMode background = BackgroundMode::Learn;
  int learn_frames = 10;
  int threshold = 28;      // grey levels of |frame − gain·background| that make a pixel foreground
  // Colour (YUYV frames and a background with chroma; threshold_colour.cpp):
  // a pixel pair whose chroma differs from the background's by more than
  // this (|ΔU| + |ΔV| at the background's brightness) is foreground
  // whatever its luma; 0: luma alone.
  int chroma_threshold = 12;
  // A pixel darker than the background but no darker than this fraction
  // of it, keeping the background's colour, is a shadow, not the person;
  // 1: no shadow is removed. Only with colour.
  double shadow_ratio = 0.5;
  int min_blob_px = 600;   // smaller blobs are noise
  double second_blob_fraction = 0.25;  // a second blob this large (of the first) → two_blobs
  BackgroundAdaptation adaptation;     // keeping the background up to date
  bool bootstrap = true;               // no background and the subject in view: build one
  BootstrapOptions bootstrapping;
};

enum class SilhouetteStatus : std::uint8_t {
  LearningBackground,  // no background yet, learning an empty scene; the mask is empty
  NoBackground,        // no background and the scene is not empty: bootstrapping; the mask is empty
  NoPerson,            // no blob of min_blob_px
  Person,              // one person blob, inside the image
  TwoBlobs,            // a second large blob (another person, an object)
  Occluded,            // the person's blob is cut by the left or right image border
};
std::string_view to_string(SilhouetteStatus status);
// The FitDiagnostics flag for a status that is not a clean person ("" if clean).
std::string_view flag_of(SilhouetteStatus status);

struct SilhouetteResult {
  SilhouetteStatus status = SilhouetteStatus::LearningBackground;
  BitMask mask;                  // the largest blob only (empty image when none)
  std::int64_t pixels = 0;       // set pixels of mask
  double gain = 1.0;             // estimated frame / background exposure ratio
  int blobs = 0;                 // blobs of at least min_blob_px
  std::int64_t second_blob_px = 0;
  // Where the view cannot tell the person from the background: pixels
  // outside the person's blob that differ from the background by more
  // than half the threshold, in regions at least 3 px thick (open_square;
  // a thinner band is a blurred outline, not a region). Dark trousers
  // before a black chair differ from it by less than the threshold and
  // more than half of it; the fit neither pays for a model drawn there nor
  // requires one (docs/cvsm.md, "A black chair"). Grey frames only (in
  // colour the chroma tells, and a shadow differs by its luma); empty
  // without a person or with BackgroundMode::Threshold.
  BitMask unseen;
  // The person's outline pixels where the stored background has an edge
  // of its own (a step of luma: a desk's side against the wall), not a
  // plain stretch of scene: where the person may end on something in
  // front of them (docs/cvsm.md, "A desk's side"). Empty without a person
  // or with BackgroundMode::Threshold.
  BitMask scene_edge;
};

class SilhouetteExtractor {
 public:
  explicit SilhouetteExtractor(SilhouetteOptions options = {});

  // Replaces the background with a stored image (BackgroundMode::Image,
  // or Learn with a stored background: no learning needed).
  Status set_background(const LumaView& background);
  bool background_ready() const;
  // Drops the background, to learn it again from the next frames of an
  // empty scene (or bootstrap it with the subject in view), as at start:
  // an operator asked for it after the scene changed. Only with
  // BackgroundMode::Learn (false otherwise: a stored image or the plain
  // threshold stays).
  bool relearn_background();
  const std::vector<std::uint8_t>& background() const { return model_.pixels(); }
  const BackgroundModel& background_model() const { return model_; }
  // Where the subject can be in this view, for bootstrapping (see
  // BackgroundBootstrap::set_prior).
  void set_person_prior(const BitMask& region) { bootstrap_.set_prior(region); }
  // The last bootstrap attempt (while status is NoBackground).
  const BootstrapAttempt& bootstrap_attempt() const { return bootstrap_.last_attempt(); }

  // The silhouette of this frame. With a `gate` (the tracked model's
  // outline, grown), only foreground inside it can be the person: a
  // passer-by behind the subject, a moved chair, a shadow further away do
  // not join the subject's blob.
  SilhouetteResult extract(const LumaView& frame, const BitMask* gate = nullptr);
  // Then the background adapts to the same frame, outside `person`: the
  // fitted model's outline when the fit is tracking (the blob would hold
  // stale background the subject just uncovered, and keep it stale), the
  // last blob otherwise (nullptr).
  void adapt(const LumaView& frame, const BitMask* person = nullptr);

 private:
  SilhouetteStatus start_background(const LumaView& frame);
  double estimate_gain(const LumaView& frame) const;
  void threshold_to_bits(const LumaView& frame, double gain, BitMask& out) const;
  bool colour(const LumaView& frame) const;
  void find_unseen(const LumaView& frame, SilhouetteResult& result) const;
  bool beside_person_still(const BitMask& person);

  SilhouetteOptions options_;
  int width_ = 0, height_ = 0;
  BackgroundModel model_;
  BackgroundBootstrap bootstrap_;
  bool bootstrapping_ = false;  // the learning frames moved: bootstrap instead
  BitMask foreground_;          // every blob of the last frame, for the adaptation
  BitMask person_;              // the last frame's person blob (empty: none)
  double gain_ = 1.0;           // the last frame's exposure gain
  StillScenery scenery_;        // whether the foreground beside the person keeps still
  BitMask beside_;              // scratch: the foreground outside the person's blob
};

// Cleaning steps, exposed for tests.
// 3×3-cross closing: fills one-pixel holes and cracks left by shading that
// matches the background.
void close_cross(BitMask& mask);
struct BlobSummary {
  std::int64_t largest_px = 0, second_px = 0;
  int blobs = 0;  // of at least min_px
  int fragments = 0;  // blobs of at least min_px kept with the largest as pieces of it
  int x_min = 0, x_max = -1, y_min = 0, y_max = -1;  // bounding box of what is kept
};
// Morphological opening by a (2·radius + 1)² square: what survives lies in
// a square of that size wholly inside the mask (the image's outside counts
// as inside, as OpenCV's erosion has it).
void open_square(BitMask& mask, int radius);
// Keeps only the largest 8-connected blob of `mask` (run-based labelling)
// and the blobs of at least min_px that are fragments of it — above or
// below it within its columns (docs/cvsm.md, "Silhouettes"); largest_px
// counts them all, second_px is the largest blob not kept.
BlobSummary keep_largest_blob(BitMask& mask, int min_px);

}  // namespace spinewatch
