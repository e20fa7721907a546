#pragma once
// A V4L2 capture device emulated in memory, for tests and benchmarks. It
// answers the ioctl sequence a camera makes (QUERYCAP, S_FMT/G_FMT with the
// driver's own bytesperline, S_PARM, controls, REQBUFS/QUERYBUF/mmap of its
// own buffers, QBUF/DQBUF, STREAMON/OFF, ENUM_FMT/ENUM_FRAMESIZES) and can
// misbehave on cue: error frames, dropped sequence numbers, a stall, ENODEV
// or POLLERR mid-stream, a device that disappears and comes back.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "spinewatch/capture/v4l2_device.hpp"
#include "spinewatch/frames/pixel_format.hpp"

namespace spinewatch {

struct FakeV4l2Script {
  std::string path = "/dev/video-fake";
  std::string card = "Fake Camera";
  std::uint32_t capabilities = 0x04000001;  // V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING
  std::vector<PixelFormat> formats = {PixelFormat::YUYV, PixelFormat::GREY};
  std::uint32_t bytesperline_align = 1;  // the driver rounds bytesperline up to this
  bool timeperframe = true;              // V4L2_CAP_TIMEPERFRAME
  std::set<std::uint32_t> missing_controls;
  std::uint32_t max_buffers = 8;
  std::uint32_t timestamp_flags = 0x2000;  // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC
  bool paced = false;                      // frames ready at their time, else at once
  // Driver sequence numbers (counted from STREAMON) of frames that come
  // back flagged V4L2_BUF_FLAG_ERROR, or that are skipped (never delivered).
  std::set<std::uint64_t> error_sequences;
  std::set<std::uint64_t> skipped_sequences;
  // After this many frames delivered in a stream (0 = never):
  std::uint64_t stall_after = 0;    // no more frames (EAGAIN), the device stays
  std::uint64_t unplug_after = 0;   // ENODEV and POLLERR; the node disappears
  std::uint64_t pollerr_after = 0;  // POLLERR once; the device stays
  int reopen_failures = 2;          // opens that fail (ENOENT) after an unplug
  bool fill = true;                 // write the pattern into each frame (off: benchmarks)
  // When set, writes each frame instead of the pattern: (driver sequence,
  // the buffer, its bytesperline). Called with the device's lock held, on
  // the thread that dequeues; it must not call back into the device.
  std::function<void(std::uint64_t seq, std::uint8_t* bytes, std::uint32_t bytesperline)> content;
};

class FakeV4l2Device final : public V4l2Device {
 public:
  explicit FakeV4l2Device(FakeV4l2Script script = {});

  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int prot, int flags, int fd, off_t offset) override;
  int munmap(void* address, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

  // The byte the fake writes at (x, y) of the frame with driver sequence `seq`.
  static std::uint8_t pattern(std::uint64_t seq, std::uint32_t x, std::uint32_t y);
  static constexpr std::uint8_t kPadding = 0xEE;

  // Inspection, for tests.
  int open_fds() const;
  int mapped_buffers() const;
  int queued_buffers() const;
  std::uint64_t frames_delivered() const;
  std::uint64_t stream_starts() const;
  std::map<std::uint32_t, std::int32_t> controls() const;
  double frame_rate() const;
  bool unplugged() const;

 private:
  struct Buffer {
    std::vector<std::uint8_t> bytes;
    bool queued = false;
    int mappings = 0;
  };

  bool is_fake_fd(int fd) const { return fd >= kFirstFd; }
  bool frame_ready_locked() const;
  std::int64_t next_frame_time_locked() const;
  int dequeue_locked(void* arg);
  int fail(int error) const;

  static constexpr int kFirstFd = 1 << 20;
  mutable std::mutex mutex_;
  FakeV4l2Script script_;
  std::set<int> fds_;
  int next_fd_ = kFirstFd;
  // Negotiated state.
  PixelFormat format_ = PixelFormat::YUYV;
  std::uint32_t width_ = 320, height_ = 240, bytesperline_ = 640;
  std::uint32_t fps_num_ = 1, fps_den_ = 30;  // time per frame
  std::map<std::uint32_t, std::int32_t> controls_;
  void release_queue_locked();

  std::vector<std::unique_ptr<Buffer>> buffers_;
  std::vector<std::unique_ptr<Buffer>> retired_;  // freed by the driver, still mapped
  int owner_fd_ = -1;                             // the file handle that owns the buffers
  std::vector<std::uint32_t> queue_;  // indices in QBUF order
  bool streaming_ = false;
  std::int64_t stream_start_ns_ = 0;
  std::uint64_t next_sequence_ = 0;
  std::uint64_t delivered_in_stream_ = 0;
  std::uint64_t delivered_total_ = 0;
  std::uint64_t stream_starts_ = 0;
  bool unplugged_ = false;
  bool pollerr_pending_ = false;
  bool pollerr_done_ = false;
  int reopen_failures_left_ = 0;
};

}  // namespace spinewatch
