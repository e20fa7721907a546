#pragma once
// One V4L2 camera: negotiates the format, frame rate, exposure and gain,
// streams through ≥ 4 mmap buffers and hands out every frame in order. A
// Frame holds a lease on its buffer; the buffer goes back to the driver when
// the last copy of the Frame is released, never before. A lost device
// (unplugged, ENODEV, POLLERR) is closed, logged once and reopened with
// backoff while the caller keeps calling next().
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "spinewatch/capture/camera.hpp"
#include "spinewatch/capture/v4l2_device.hpp"
#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

namespace v4l2 {
class StreamSession;
}

struct V4l2CameraOptions {
  std::string path = "/dev/video0";
  std::string name;  // for log lines ("frontal"); the path when empty
  PixelFormat pixel_format = PixelFormat::YUYV;
  std::uint32_t width = 320;
  std::uint32_t height = 240;
  double fps = 30.0;
  int exposure_us = 0;  // 0: leave exposure to the driver
  int gain = -1;        // −1: leave gain to the driver
  unsigned buffers = 4;
  double watchdog_s = 2.0;  // report a camera silent this long; 0 = off
  std::chrono::milliseconds retry_initial{250};
  std::chrono::milliseconds retry_max{4000};
};

class V4l2Camera final : public Camera {
 public:
  explicit V4l2Camera(V4l2CameraOptions options, std::shared_ptr<V4l2Device> device = system_v4l2_device());
  ~V4l2Camera();
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  // Opens, configures and starts streaming. The error names the device and
  // the problem; control the driver lacks are warnings only.
  Status start() override;
  // The next frame in driver order; nothing on timeout or once stopped
  // (a negative timeout waits until a frame comes or stop()).
  // Called from one thread. Device loss and recovery happen inside.
  std::optional<Frame> next(std::chrono::milliseconds timeout) override;
  // From any thread: wakes next() and makes it return nothing from now on.
  void stop() override;

  CameraCounters counters() const override;
  FrameFormat format() const override;  // as negotiated with the driver
  double fps() const override;          // as the driver reported it
  bool streaming() const { return streaming_.load(); }
  bool stalled() const { return stalled_.load(); }
  const std::string& name() const override { return name_; }

 private:
  Status open_session();
  void lose_device(const std::string& why);
  void try_reopen();
  void check_watchdog(std::int64_t now_ns);

  V4l2CameraOptions options_;
  std::string name_;
  std::shared_ptr<V4l2Device> device_;
  std::shared_ptr<v4l2::StreamSession> session_;
  int wake_fd_ = -1;
  std::atomic<bool> stopped_{false};
  std::atomic<bool> streaming_{false};
  std::atomic<bool> stalled_{false};
  mutable std::mutex format_mutex_;
  FrameFormat format_{};
  double fps_ = 0.0;
  // Sequence numbers continue across restarts (drivers count from 0 at
  // STREAMON), so downstream never sees a number twice.
  std::uint64_t sequence_base_ = 0;
  std::optional<std::uint64_t> last_driver_sequence_;
  std::uint64_t next_sequence_ = 0;
  std::int64_t last_frame_ns_ = 0;
  std::int64_t retry_at_ns_ = 0;
  std::chrono::milliseconds backoff_{0};
  bool warned_clock_ = false;
  std::atomic<std::uint64_t> frames_{0}, dropped_error_{0}, dropped_gap_{0}, restarts_{0}, stalls_{0}, losses_{0};
};

}  // namespace spinewatch
