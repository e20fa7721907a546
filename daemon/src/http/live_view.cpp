#include "http/live_view.hpp"

#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "pipeline/pipeline.hpp"
#include "spinewatch/frames/clock.hpp"
#include "spinewatch/overlay/overlay.hpp"

namespace spinewatch {

LiveView::LiveView(CameraRig rig, LiveViewOptions options, FrameFn on_frame)
    : rig_(std::move(rig)),
      options_(options),
      period_ns_(static_cast<std::int64_t>(1e9 / std::max(0.1, options.fps))),
      on_frame_(std::move(on_frame)) {
  thread_ = std::jthread([this] { run(); });
}

LiveView::~LiveView() { stop(); }

void LiveView::stop() {
  if (stopped_) return;
  stopped_ = true;
  mailbox_.close();
  if (thread_.joinable()) thread_.join();
}

void LiveView::want_picture_until(std::int64_t until_ns) {
  std::int64_t current = picture_until_ns_.load();
  while (current < until_ns && !picture_until_ns_.compare_exchange_weak(current, until_ns)) {
  }
}

void LiveView::want_state_until(std::int64_t until_ns) {
  std::int64_t current = state_until_ns_.load();
  while (current < until_ns && !state_until_ns_.compare_exchange_weak(current, until_ns)) {
  }
}

void LiveView::offer(const FramePair& pair, const Posture& posture, const EstimatorTrace& trace) {
  const bool viewers = viewers_.load(std::memory_order_relaxed) > 0;
  const std::int64_t picture_until = picture_until_ns_.load(std::memory_order_relaxed);
  const std::int64_t state_until = state_until_ns_.load(std::memory_order_relaxed);
  if (!viewers && picture_until == 0 && state_until == 0) return;
  const std::int64_t now = monotonic_now_ns();
  const bool picture = viewers || now < picture_until;
  if (!picture && now >= state_until) return;
  if (now - last_offer_ns_ < period_ns_) return;
  last_offer_ns_ = now;

  Sample sample;
  sample.summary.posture = posture;
  sample.summary.taken_ns = now;
  sample.picture = picture;
  for (int v = 0; v < 2; ++v) {
    sample.summary.background[v] = trace.background_source[v];
    if (trace.silhouette[v]) {
      sample.summary.coverage[v] = view_coverage(*trace.silhouette[v]);
      if (picture) sample.silhouette[v] = *trace.silhouette[v];
    }
  }
  const FrameFormat& format = pair.frontal.format();
  sample.width = static_cast<int>(format.width);
  sample.height = static_cast<int>(format.height);
  if (picture) {
    if (trace.fit) sample.fit = *trace.fit;
    if (trace.body_model) sample.body_model = std::make_shared<const BodyModel>(*trace.body_model);
    // Frames hold their pixels through a shared handle: a copy is a reference.
    if (options_.camera_pixels) sample.pair = pair;
  }
  samples_.fetch_add(1, std::memory_order_relaxed);
  if (mailbox_.push(std::move(sample))) samples_dropped_.fetch_add(1, std::memory_order_relaxed);
}

std::shared_ptr<const std::string> LiveView::render(const Sample& s) {
  OverlayScene scene;
  scene.rig = &rig_;
  scene.width = s.width;
  scene.height = s.height;
  if (s.pair) {
    scene.frames[0] = &s.pair->frontal;
    scene.frames[1] = &s.pair->lateral;
  }
  for (int v = 0; v < 2; ++v) scene.silhouette[v] = s.silhouette[v].empty() ? nullptr : &s.silhouette[v];
  scene.fit = s.fit ? &*s.fit : nullptr;
  scene.body_model = s.body_model.get();
  scene.posture = &s.summary.posture;
  scene.note = options_.note;
  const cv::Mat image = render_overlay(scene, OverlayOptions{.scale = options_.scale});
  auto jpeg = jpeg_.encode(image, options_.jpeg_quality);
  if (!jpeg) {
    // Once: a compressor that fails fails for every picture, at http.fps a
    // second; the live frames counter (metrics) stops rising meanwhile.
    if (!jpeg_failure_logged_)
      spdlog::error("live view: pair {}: {} (further failures are not logged)", s.summary.posture.seq,
                    jpeg.error().message);
    jpeg_failure_logged_ = true;
    return nullptr;
  }
  return std::make_shared<const std::string>(std::move(jpeg).value());
}

void LiveView::run() {
  while (auto sample = mailbox_.pop()) {
    auto frame = std::make_shared<LiveFrame>();
    if (sample->picture && sample->width > 0) {
      const auto t0 = std::chrono::steady_clock::now();
      try {
        frame->jpeg = render(*sample);
      } catch (const std::exception& e) {
        spdlog::error("live view: drawing pair {} failed: {}", sample->summary.posture.seq, e.what());
      }
      const auto us = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
      render_us_.fetch_add(static_cast<std::uint64_t>(us.count()), std::memory_order_relaxed);
      if (frame->jpeg) frames_.fetch_add(1, std::memory_order_relaxed);
    }
    frame->summary = std::move(sample->summary);
    on_frame_(std::move(frame));
  }
}

LiveViewStats LiveView::stats() const {
  LiveViewStats s;
  s.samples = samples_.load(std::memory_order_relaxed);
  s.samples_dropped = samples_dropped_.load(std::memory_order_relaxed);
  s.frames = frames_.load(std::memory_order_relaxed);
  s.render_us = render_us_.load(std::memory_order_relaxed);
  s.mailbox = mailbox_.size();
  s.mailbox_capacity = mailbox_.capacity();
  return s;
}

}  // namespace spinewatch
