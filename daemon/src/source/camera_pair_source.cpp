#include "spinewatch/daemon/camera_pair_source.hpp"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "spinewatch/frames/clock.hpp"
#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch {
namespace {

// Frames wait in the pairer and pairs in the queue as copies, not as the
// driver's buffers: a camera with 4 mmap buffers must never wait for a
// partner that stalls, a trigger that stopped or a busy pipeline (the
// pairer may hold 16 frames per camera).
// How long a capture thread waits for a frame before it looks at the
// camera's loss counter again.
constexpr std::chrono::milliseconds kLossCheck{200};

Frame detached(const Frame& frame) { return Frame::copy_of(frame.format(), frame.info(), frame.bytes()); }

class CameraPairSource final : public PairSource {
 public:
  // Any Camera: V4L2 or libcamera.
  CameraPairSource(std::unique_ptr<Camera> frontal, std::unique_ptr<Camera> lateral, sync::PairerOptions pairing,
                   std::size_t ready_pairs, std::string description)
      : ready_limit_(ready_pairs == 0 ? 1 : ready_pairs),
        pairer_(pairing),
        description_(std::move(description)) {
    cameras_[0] = std::move(frontal);
    cameras_[1] = std::move(lateral);
  }
  ~CameraPairSource() override { stop(); }

  // The trigger starts first, so the first frames find their edges.
  Status start(const TriggerFactory& make_trigger) {
    if (make_trigger) {
      auto trigger = make_trigger([this](std::int64_t edge_ns) {
        std::lock_guard lock(mutex_);
        if (stopped_) return;
        pairer_.push_trigger(edge_ns);
        queue_pairs();
      });
      if (!trigger) return trigger.error();
      trigger_ = std::move(trigger).value();
    }
    for (auto& camera : cameras_)
      if (auto started = camera->start(); !started) return started;
    for (int i = 0; i < 2; ++i) threads_[i] = std::jthread([this, i] { capture(i); });
    return Ok{};
  }

  std::optional<FramePair> next() override {
    std::unique_lock lock(mutex_);
    ready_cv_.wait(lock, [&] { return stopped_ || !ready_.empty(); });
    if (ready_.empty()) return std::nullopt;
    FramePair pair = std::move(ready_.front());
    ready_.pop_front();
    return pair;
  }

  void stop() override {
    {
      std::lock_guard lock(mutex_);
      if (stopped_) return;
      stopped_ = true;
    }
    if (trigger_) trigger_->stop();
    for (auto& camera : cameras_) camera->stop();
    ready_cv_.notify_all();
    for (auto& t : threads_)
      if (t.joinable()) t.join();
  }

  SourceStats stats() const override {
    std::lock_guard lock(mutex_);
    const auto& s = pairer_.stats();
    SourceStats out;
    out.frames = s.frames_in[0] + s.frames_in[1];
    out.frames_lost = 2 * pairs_overflowed_;
    for (const auto& d : s.drops) out.frames_lost += d.total_discarded() + d.sequence_gaps;
    for (int i = 0; i < 2; ++i) {
      const CameraCounters c = cameras_[i]->counters();
      out.frames_lost += c.dropped_error;
      out.camera[i] = {.frames = c.frames, .restarts = c.restarts, .losses = c.losses};
    }
    return out;
  }

  std::string describe() const override { return description_; }

 private:
  void capture(int index) {
    auto& camera = *cameras_[index];
    std::uint64_t losses_seen = camera.counters().losses;
    for (;;) {
      // A bounded wait, so that a loss is marked while the device is away
      // (the camera reopens it by itself, inside next()).
      auto frame = camera.next(kLossCheck);
      if (const std::uint64_t losses = camera.counters().losses; losses != losses_seen) {
        losses_seen = losses;
        std::lock_guard lock(mutex_);
        if (stopped_) return;
        mark_camera_lost();
      }
      if (!frame) {
        std::lock_guard lock(mutex_);
        if (stopped_) return;
        continue;  // timeout, or a camera that is away
      }
      Frame copy = detached(*frame);
      frame.reset();  // the buffer goes back to the driver now
      std::lock_guard lock(mutex_);
      if (stopped_) return;
      pairer_.push(kViews[index], std::move(copy));
      queue_pairs();
    }
  }

  // With mutex_ held: one marker per loss, in order with the pairs. Its
  // time is the last pair's: the gap begins after it, and t_ns never goes
  // back in the stream (frames still in the pairer may pair after the
  // marker, and they are older than the moment the loss was seen).
  void mark_camera_lost() {
    FramePair marker;
    marker.timestamp_ns = last_pair_ns_ ? *last_pair_ns_ : monotonic_now_ns();
    marker.camera_lost = true;
    push_ready(std::move(marker));
  }

  // With mutex_ held.
  void push_ready(FramePair pair) {
    if (!pair.camera_lost) last_pair_ns_ = pair.timestamp_ns;
    if (ready_.size() >= ready_limit_) {
      ready_.pop_front();
      ++pairs_overflowed_;
    }
    ready_.push_back(std::move(pair));
    ready_cv_.notify_one();
  }

  // With mutex_ held.
  void queue_pairs() {
    while (auto pair = pairer_.pop()) push_ready(std::move(*pair));
  }

  const std::size_t ready_limit_;
  std::unique_ptr<Camera> cameras_[2];
  mutable std::mutex mutex_;
  std::condition_variable ready_cv_;
  sync::FramePairer pairer_;
  std::deque<FramePair> ready_;
  std::uint64_t pairs_overflowed_ = 0;
  std::optional<std::int64_t> last_pair_ns_;  // of the last pair queued
  bool stopped_ = false;
  std::string description_;
  std::unique_ptr<sync::TriggerSource> trigger_;  // null in free-run
  std::jthread threads_[2];
};

TriggerFactory default_trigger(const CameraPairOptions& options) {
  if (options.trigger.mode == sync::TriggerMode::FreeRun) return {};
  return [trigger = options.trigger](sync::TriggerSource::EdgeCallback on_edge) {
    return sync::TriggerSource::open(trigger, std::move(on_edge));
  };
}

}  // namespace

sync::PairerOptions pairer_options(const CameraPairOptions& options) {
  sync::PairerOptions p{.fps = options.frontal.fps, .triggered = options.trigger.mode != sync::TriggerMode::FreeRun};
  p.frame_latency_ns[0] = p.frame_latency_ns[1] = options.frame_latency_ns;
  return p;
}

CameraPairOptions camera_pair_options(const Config& config) {
  auto camera = [&](const std::string& path, const char* name) {
    V4l2CameraOptions o;
    o.path = path;
    o.name = name;
    o.pixel_format = config.cameras.pixel_format;
    o.width = static_cast<std::uint32_t>(config.cameras.width);
    o.height = static_cast<std::uint32_t>(config.cameras.height);
    o.fps = config.cameras.fps;
    o.exposure_us = config.cameras.exposure_us;
    o.gain = config.cameras.gain;
    o.buffers = static_cast<unsigned>(config.cameras.buffers);
    o.watchdog_s = config.cameras.watchdog_s;
    return o;
  };
  CameraPairOptions options;
  options.frontal = camera(config.cameras.frontal, "frontal");
  options.lateral = camera(config.cameras.lateral, "lateral");
  options.trigger = {.mode = config.trigger.mode, .chip = config.trigger.chip,
                     .line = static_cast<unsigned>(config.trigger.line), .fps = config.cameras.fps,
                     .pulse_us = config.trigger.pulse_us, .consumer = "spinewatchd"};
  options.frame_latency_ns = std::int64_t{config.trigger.frame_latency_us} * 1000;
  return options;
}

Result<std::unique_ptr<PairSource>> open_camera_pair_source(const CameraPairOptions& options,
                                                            std::shared_ptr<V4l2Device> frontal,
                                                            std::shared_ptr<V4l2Device> lateral,
                                                            TriggerFactory make_trigger) {
  auto source = std::make_unique<CameraPairSource>(
      std::make_unique<V4l2Camera>(options.frontal, std::move(frontal)),
      std::make_unique<V4l2Camera>(options.lateral, std::move(lateral)), pairer_options(options), options.ready_pairs,
      fmt::format("v4l2 {} {}", options.frontal.path, options.lateral.path));
  if (auto started = source->start(make_trigger ? make_trigger : default_trigger(options)); !started)
    return started.error();
  return std::unique_ptr<PairSource>(std::move(source));
}

Result<std::unique_ptr<PairSource>> open_libcamera_pair_source(const Config& config) {
  const CameraPairOptions v4l2 = camera_pair_options(config);
  auto camera = [](const V4l2CameraOptions& o) {
    return LibcameraCamera::open({.id = o.path, .name = o.name, .pixel_format = o.pixel_format, .width = o.width,
                                  .height = o.height, .fps = o.fps, .exposure_us = o.exposure_us, .gain = o.gain,
                                  .buffers = o.buffers});
  };
  auto frontal = camera(v4l2.frontal);
  if (!frontal) return frontal.error();
  auto lateral = camera(v4l2.lateral);
  if (!lateral) return lateral.error();
  auto source = std::make_unique<CameraPairSource>(
      std::move(frontal).value(), std::move(lateral).value(), pairer_options(v4l2), v4l2.ready_pairs,
      fmt::format("libcamera \"{}\" \"{}\"", v4l2.frontal.path, v4l2.lateral.path));
  if (auto started = source->start(default_trigger(v4l2)); !started) return started.error();
  return std::unique_ptr<PairSource>(std::move(source));
}

}  // namespace spinewatch
