#pragma once
// The live view's pictures (docs/interfaces.md §5, /stream and /snapshot): what
// the estimator saw and fitted, drawn (spinewatch/overlay) and encoded as
// JPEG on a thread of its own, at most `fps` times a second and only while
// someone wants it — so that viewers cost the pipeline nothing measurable.
//
// The estimator thread calls offer() after every pair. Unless a viewer
// wants a picture and one is due, offer() returns after two atomic loads
// and a clock read; when one is, it copies what the drawing needs (the two
// silhouette bitmasks, the fit, the subject's model, the posture; the
// frames themselves only with camera_pixels) into a bounded mailbox whose
// oldest entry is dropped (and counted) when the render thread is behind.
// The render thread draws, encodes and hands each LiveFrame to `on_frame`.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/cvsm/tracker.hpp"
#include "spinewatch/estimator/pipeline.hpp"
#include "spinewatch/estimator/posture.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "spinewatch/estimator/silhouette/view_coverage.hpp"
#include "spinewatch/frames/frame_pair.hpp"
#include "http/jpeg_encoder.hpp"
#include "support/bounded_queue.hpp"

namespace spinewatch {

struct LiveViewOptions {
  double fps = 5.0;            // pictures (and state samples) a second at most
  bool camera_pixels = false;  // draw over the cameras' pixels; else a plain background (privacy)
  int jpeg_quality = 80;
  int scale = 2;               // camera pixel → overlay pixels
  std::string note{};          // on every picture's text strip (the station's name)
};

// What /state shows of the latest sample (no pixels).
struct LiveSummary {
  Posture posture;
  ViewCoverage coverage[2];
  BackgroundSource background[2] = {BackgroundSource::None, BackgroundSource::None};
  std::int64_t taken_ns = 0;  // CLOCK_MONOTONIC when the estimator handed it over
};

struct LiveFrame {
  LiveSummary summary;
  std::shared_ptr<const std::string> jpeg;  // null when nobody wanted a picture
};

struct LiveViewStats {
  std::uint64_t samples = 0;          // handed over by the estimator thread
  std::uint64_t samples_dropped = 0;  // dropped from the mailbox (render thread behind)
  std::uint64_t frames = 0;           // JPEGs encoded
  std::uint64_t render_us = 0;        // time spent drawing and encoding, all frames
  std::size_t mailbox = 0, mailbox_capacity = 0;
};

class LiveView {
 public:
  using FrameFn = std::function<void(std::shared_ptr<const LiveFrame>)>;
  LiveView(CameraRig rig, LiveViewOptions options, FrameFn on_frame);
  ~LiveView();  // stop()
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  // Estimator thread, after every pair.
  void offer(const FramePair& pair, const Posture& posture, const EstimatorTrace& trace);

  // Any thread. Pictures are wanted while viewers are counted, or until
  // `until_ns` (CLOCK_MONOTONIC) for one-off requests; samples without
  // pictures while state is wanted.
  void add_viewer() { viewers_.fetch_add(1); }
  void remove_viewer() { viewers_.fetch_sub(1); }
  void want_picture_until(std::int64_t until_ns);
  void want_state_until(std::int64_t until_ns);

  void stop();
  LiveViewStats stats() const;
  const LiveViewOptions& options() const { return options_; }

 private:
  struct Sample {
    LiveSummary summary;
    BitMask silhouette[2];
    std::optional<CvsmResult> fit;
    std::shared_ptr<const BodyModel> body_model;
    std::optional<FramePair> pair;  // camera_pixels only
    int width = 0, height = 0;
    bool picture = false;
  };
  void run();
  std::shared_ptr<const std::string> render(const Sample& sample);

  const CameraRig rig_;
  const LiveViewOptions options_;
  const std::int64_t period_ns_;
  FrameFn on_frame_;
  BoundedQueue<Sample> mailbox_{2};
  std::atomic<int> viewers_{0};
  std::atomic<std::int64_t> picture_until_ns_{0}, state_until_ns_{0};
  std::int64_t last_offer_ns_ = 0;  // estimator thread only
  std::atomic<std::uint64_t> samples_{0}, samples_dropped_{0}, frames_{0}, render_us_{0};
  JpegEncoder jpeg_;                  // render thread only
  bool jpeg_failure_logged_ = false;  // render thread only
  std::jthread thread_;
  bool stopped_ = false;
};

}  // namespace spinewatch
