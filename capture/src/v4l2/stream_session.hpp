#pragma once
// One open-configure-stream cycle of a V4L2 device: the fd, the negotiated
// format and the mmap buffers. Shared between the camera and the leases of
// the frames it handed out, so buffers stay mapped while any frame uses them.
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "device_handles.hpp"
#include "spinewatch/capture/v4l2_camera.hpp"

namespace spinewatch::v4l2 {

struct Dequeued {
  std::uint32_t index = 0;
  std::uint32_t sequence = 0;
  std::uint32_t flags = 0;
  std::uint32_t bytesused = 0;
  std::int64_t timestamp_ns = 0;
};

class StreamSession {
 public:
  static Result<std::shared_ptr<StreamSession>> open(std::shared_ptr<V4l2Device> device,
                                                     const V4l2CameraOptions& options, const std::string& name);
  ~StreamSession();
  StreamSession(const StreamSession&) = delete;
  StreamSession& operator=(const StreamSession&) = delete;

  int fd() const { return fd_.get(); }
  const FrameFormat& format() const { return format_; }
  double fps() const { return fps_; }
  std::size_t buffer_count() const { return buffers_.size(); }

  // DQBUF: 0 and the buffer, or the errno (EAGAIN: nothing ready).
  int dequeue(Dequeued& out);
  std::span<const std::uint8_t> bytes(std::uint32_t index) const;
  // Gives a buffer back to the driver (any thread); nothing once shut down.
  void requeue(std::uint32_t index);
  // Stops streaming and closes the device; mappings stay until the last lease goes.
  void shutdown();

 private:
  StreamSession(std::shared_ptr<V4l2Device> device, std::string name) : device_(std::move(device)), name_(std::move(name)) {}
  Status configure(const V4l2CameraOptions& options);
  Status set_format(const V4l2CameraOptions& options);
  void set_frame_rate(double fps);
  void set_control(std::uint32_t id, std::int32_t value, const char* what);
  Status map_buffers(unsigned count);
  Status start_streaming();
  int xioctl(unsigned long request, void* arg) { return device_->ioctl(fd_.get(), request, arg); }

  std::shared_ptr<V4l2Device> device_;
  std::string name_;
  std::mutex mutex_;  // requeue() against shutdown()
  bool live_ = false;
  DeviceFd fd_;
  std::vector<MappedBuffer> buffers_;  // after fd_: unmapped before the fd closes
  FrameFormat format_{};
  double fps_ = 0.0;
};

}  // namespace spinewatch::v4l2
