#pragma once
// A V4L2 video output device that keeps showing one image: a feeder thread
// takes every buffer the driver hands back, fills it with the current image
// and queues it again, so the stream never runs dry (vivid's loop shows its
// test pattern whenever the output queue is empty).
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::kernel_test {

class VideoOutput {
 public:
  // Opens `path`, sets `format` and allocates the buffers; nothing streams yet.
  static Result<std::unique_ptr<VideoOutput>> open(const std::string& path, FrameFormat format);
  ~VideoOutput();
  VideoOutput(const VideoOutput&) = delete;
  VideoOutput& operator=(const VideoOutput&) = delete;

  // The image every buffer queued from now on carries (bytesperline × height bytes).
  void show(std::span<const std::uint8_t> image);
  // Queues every buffer with the current image and starts the stream and the feeder.
  Status start();
  const FrameFormat& format() const { return format_; }
  std::uint64_t buffers_fed() const { return fed_.load(); }

 private:
  struct Mapping {
    void* address = nullptr;
    std::size_t length = 0;
  };
  VideoOutput() = default;
  Status queue(std::uint32_t index);
  void feed();

  int fd_ = -1;
  FrameFormat format_{};
  std::vector<Mapping> buffers_;
  std::mutex mutex_;  // image_
  std::vector<std::uint8_t> image_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> fed_{0};
  bool streaming_ = false;
  std::thread feeder_;
};

}  // namespace spinewatch::kernel_test
