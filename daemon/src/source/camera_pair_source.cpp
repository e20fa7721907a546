#include "spinewatch/daemon/camera_pair_source.hpp"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "spinewatch/sync/frame_pairer.hpp"

namespace spinewatch {
namespace {

// Pairs leave holding copies, not the V4L2 buffers: the pipeline may hold a
// few pairs, and a camera with 4 mmap buffers must never wait for them.
Frame detached(const Frame& frame) { return Frame::copy_of(frame.format(), frame.info(), frame.bytes()); }

class CameraPairSource final : public PairSource {
 public:
  // Any Camera: V4L2 or libcamera.
  CameraPairSource(std::unique_ptr<Camera> frontal, std::unique_ptr<Camera> lateral, double fps,
                   std::size_t ready_pairs, std::string description)
      : ready_limit_(ready_pairs == 0 ? 1 : ready_pairs),
        pairer_(sync::PairerOptions{.fps = fps}),
        description_(std::move(description)) {
    cameras_[0] = std::move(frontal);
    cameras_[1] = std::move(lateral);
  }
  ~CameraPairSource() override { stop(); }

  Status start() {
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
    for (const auto& camera : cameras_) out.frames_lost += camera->counters().dropped_error;
    return out;
  }

  std::string describe() const override { return description_; }

 private:
  void capture(int index) {
    auto& camera = *cameras_[index];
    for (;;) {
      auto frame = camera.next(std::chrono::milliseconds(-1));
      if (!frame) return;  // stopped
      std::lock_guard lock(mutex_);
      if (stopped_) return;
      pairer_.push(static_cast<sync::Stream>(index), std::move(*frame));
      while (auto pair = pairer_.pop()) {
        pair->frontal = detached(pair->frontal);
        pair->lateral = detached(pair->lateral);
        if (ready_.size() >= ready_limit_) {
          ready_.pop_front();
          ++pairs_overflowed_;
        }
        ready_.push_back(std::move(*pair));
        ready_cv_.notify_one();
      }
    }
  }

  const std::size_t ready_limit_;
  std::unique_ptr<Camera> cameras_[2];
  mutable std::mutex mutex_;
  std::condition_variable ready_cv_;
  sync::FramePairer pairer_;
  std::deque<FramePair> ready_;
  std::uint64_t pairs_overflowed_ = 0;
  bool stopped_ = false;
  std::string description_;
  std::jthread threads_[2];
};

}  // namespace

CameraPairOptions camera_pair_options(const Config& config) {
  auto camera = [&](const std::string& path, const char* name) {
    V4l2CameraOptions o;
    o.path = path;
    o.name = name;
    o.pixel_format = parse_pixel_format(config.cameras.pixel_format).value_or(PixelFormat::YUYV);
    o.width = static_cast<std::uint32_t>(config.cameras.width);
    o.height = static_cast<std::uint32_t>(config.cameras.height);
    o.fps = config.cameras.fps;
    o.exposure_us = config.cameras.exposure_us;
    o.gain = config.cameras.gain;
    o.buffers = static_cast<unsigned>(config.cameras.buffers);
    o.watchdog_s = config.cameras.watchdog_s;
    return o;
  };
  return {camera(config.cameras.frontal, "frontal"), camera(config.cameras.lateral, "lateral")};
}

Result<std::unique_ptr<PairSource>> open_camera_pair_source(const CameraPairOptions& options,
                                                            std::shared_ptr<V4l2Device> frontal,
                                                            std::shared_ptr<V4l2Device> lateral) {
  auto source = std::make_unique<CameraPairSource>(
      std::make_unique<V4l2Camera>(options.frontal, std::move(frontal)),
      std::make_unique<V4l2Camera>(options.lateral, std::move(lateral)), options.frontal.fps, options.ready_pairs,
      fmt::format("v4l2 {} {}", options.frontal.path, options.lateral.path));
  if (auto started = source->start(); !started) return started.error();
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
      std::move(frontal).value(), std::move(lateral).value(), v4l2.frontal.fps, v4l2.ready_pairs,
      fmt::format("libcamera \"{}\" \"{}\"", v4l2.frontal.path, v4l2.lateral.path));
  if (auto started = source->start(); !started) return started.error();
  return std::unique_ptr<PairSource>(std::move(source));
}

}  // namespace spinewatch
