#include "spinewatch/capture/fake_v4l2_device.hpp"
#include "spinewatch/frames/clock.hpp"

#include <linux/videodev2.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace spinewatch {
namespace {
constexpr off_t kOffsetStep = 1 << 20;

void copy_name(std::uint8_t* dst, std::size_t size, const std::string& src) {
  std::memset(dst, 0, size);
  std::memcpy(dst, src.data(), std::min(size - 1, src.size()));
}
}  // namespace

FakeV4l2Device::FakeV4l2Device(FakeV4l2Script script) : script_(std::move(script)) {
  bytesperline_ = width_ * bytes_per_pixel(format_);
}

int FakeV4l2Device::fail(int error) const {
  errno = error;
  return -1;
}

std::uint8_t FakeV4l2Device::pattern(std::uint64_t seq, std::uint32_t x, std::uint32_t y) {
  return static_cast<std::uint8_t>(seq * 7 + x * 3 + y);
}

int FakeV4l2Device::open(const char* path, int /*flags*/) {
  std::lock_guard lock(mutex_);
  if (path != script_.path) return fail(ENOENT);
  if (unplugged_) {
    if (reopen_failures_left_ > 0) {
      --reopen_failures_left_;
      return fail(ENOENT);
    }
    // Plugged back in: a fresh device.
    unplugged_ = false;
    pollerr_pending_ = false;
  }
  const int fd = next_fd_++;
  fds_.insert(fd);
  return fd;
}

void FakeV4l2Device::release_queue_locked() {
  streaming_ = false;
  queue_.clear();
  for (auto& b : buffers_) {
    if (b->mappings > 0) retired_.push_back(std::move(b));
  }
  buffers_.clear();
  owner_fd_ = -1;
}

int FakeV4l2Device::close(int fd) {
  std::lock_guard lock(mutex_);
  if (fds_.erase(fd) == 0) return fail(EBADF);
  if (fd == owner_fd_) release_queue_locked();
  return 0;
}

std::int64_t FakeV4l2Device::next_frame_time_locked() const {
  std::uint64_t seq = next_sequence_;
  while (script_.skipped_sequences.count(seq)) ++seq;
  const double period_ns = 1e9 * fps_num_ / std::max<std::uint32_t>(fps_den_, 1);
  return stream_start_ns_ + static_cast<std::int64_t>(std::llround(static_cast<double>(seq) * period_ns));
}

bool FakeV4l2Device::frame_ready_locked() const {
  if (!streaming_ || unplugged_ || queue_.empty()) return false;
  if (script_.stall_after && delivered_in_stream_ >= script_.stall_after) return false;
  return !script_.paced || monotonic_now_ns() >= next_frame_time_locked();
}

int FakeV4l2Device::dequeue_locked(void* arg) {
  auto* b = static_cast<v4l2_buffer*>(arg);
  if (unplugged_) return fail(ENODEV);
  if (!streaming_ || b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP) return fail(EINVAL);
  if (!frame_ready_locked()) return fail(EAGAIN);
  const std::int64_t t = next_frame_time_locked();
  while (script_.skipped_sequences.count(next_sequence_)) ++next_sequence_;
  const std::uint64_t seq = next_sequence_++;
  const std::uint32_t index = queue_.front();
  queue_.erase(queue_.begin());
  Buffer& buffer = *buffers_[index];
  buffer.queued = false;
  if (script_.content) {
    script_.content(seq, buffer.bytes.data(), bytesperline_);
  } else if (script_.fill) {
    const std::uint32_t row_bytes = width_ * bytes_per_pixel(format_);
    for (std::uint32_t y = 0; y < height_; ++y) {
      std::uint8_t* row = buffer.bytes.data() + std::size_t{y} * bytesperline_;
      for (std::uint32_t x = 0; x < row_bytes; ++x) row[x] = pattern(seq, x, y);
      std::fill(row + row_bytes, row + bytesperline_, kPadding);
    }
  }
  std::memset(b, 0, sizeof(*b));
  b->index = index;
  b->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b->memory = V4L2_MEMORY_MMAP;
  b->bytesused = static_cast<std::uint32_t>(buffer.bytes.size());
  b->length = static_cast<std::uint32_t>(buffer.bytes.size());
  b->field = V4L2_FIELD_NONE;
  b->flags = script_.timestamp_flags | (script_.error_sequences.count(seq) ? V4L2_BUF_FLAG_ERROR : 0u);
  b->sequence = static_cast<std::uint32_t>(seq);
  b->timestamp.tv_sec = t / 1'000'000'000;
  b->timestamp.tv_usec = (t % 1'000'000'000) / 1000;
  ++delivered_in_stream_;
  ++delivered_total_;
  if (script_.unplug_after && delivered_in_stream_ == script_.unplug_after) {
    unplugged_ = true;
    reopen_failures_left_ = script_.reopen_failures;
  }
  if (script_.pollerr_after && delivered_in_stream_ == script_.pollerr_after && !pollerr_done_) {
    pollerr_pending_ = true;
  }
  return 0;
}

int FakeV4l2Device::ioctl(int fd, unsigned long request, void* arg) {
  std::lock_guard lock(mutex_);
  if (!fds_.count(fd)) return fail(EBADF);
  if (unplugged_) return fail(ENODEV);
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      std::memset(cap, 0, sizeof(*cap));
      copy_name(cap->driver, sizeof(cap->driver), "fakecam");
      copy_name(cap->card, sizeof(cap->card), script_.card);
      copy_name(cap->bus_info, sizeof(cap->bus_info), "platform:fakecam");
      cap->version = 0x060100;
      cap->device_caps = script_.capabilities;
      cap->capabilities = script_.capabilities | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_S_FMT:
    case VIDIOC_G_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      if (request == VIDIOC_S_FMT) {
        if (!buffers_.empty()) return fail(EBUSY);
        auto requested = from_fourcc(f->fmt.pix.pixelformat);
        const bool supported = requested && std::count(script_.formats.begin(), script_.formats.end(), *requested);
        format_ = supported ? *requested : script_.formats.front();
        width_ = std::clamp<std::uint32_t>(f->fmt.pix.width, 16, 1920) & ~1u;
        height_ = std::clamp<std::uint32_t>(f->fmt.pix.height, 16, 1080) & ~1u;
        const std::uint32_t align = std::max<std::uint32_t>(script_.bytesperline_align, 1);
        bytesperline_ = (width_ * bytes_per_pixel(format_) + align - 1) / align * align;
      }
      std::memset(&f->fmt.pix, 0, sizeof(f->fmt.pix));
      f->fmt.pix.width = width_;
      f->fmt.pix.height = height_;
      f->fmt.pix.pixelformat = fourcc(format_);
      f->fmt.pix.field = V4L2_FIELD_NONE;
      f->fmt.pix.bytesperline = bytesperline_;
      f->fmt.pix.sizeimage = bytesperline_ * height_;
      f->fmt.pix.colorspace = V4L2_COLORSPACE_SRGB;
      return 0;
    }
    case VIDIOC_S_PARM:
    case VIDIOC_G_PARM: {
      if (!script_.timeperframe) return fail(ENOTTY);
      auto* p = static_cast<v4l2_streamparm*>(arg);
      if (p->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      if (request == VIDIOC_S_PARM && p->parm.capture.timeperframe.numerator > 0 &&
          p->parm.capture.timeperframe.denominator > 0) {
        fps_num_ = p->parm.capture.timeperframe.numerator;
        fps_den_ = p->parm.capture.timeperframe.denominator;
      }
      std::memset(&p->parm, 0, sizeof(p->parm));
      p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      p->parm.capture.timeperframe = {fps_num_, fps_den_};
      return 0;
    }
    case VIDIOC_S_CTRL: {
      auto* c = static_cast<v4l2_control*>(arg);
      if (script_.missing_controls.count(c->id)) return fail(EINVAL);
      controls_[c->id] = c->value;
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* r = static_cast<v4l2_requestbuffers*>(arg);
      if (r->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || r->memory != V4L2_MEMORY_MMAP) return fail(EINVAL);
      if (streaming_) return fail(EBUSY);
      if (owner_fd_ != -1 && owner_fd_ != fd) return fail(EBUSY);
      release_queue_locked();
      r->count = std::min(r->count, script_.max_buffers);
      for (std::uint32_t i = 0; i < r->count; ++i) {
        auto buffer = std::make_unique<Buffer>();
        buffer->bytes.assign(std::size_t{bytesperline_} * height_, 0);
        buffers_.push_back(std::move(buffer));
      }
      if (r->count > 0) owner_fd_ = fd;
      return 0;
    }
    case VIDIOC_QUERYBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (fd != owner_fd_ || b->index >= buffers_.size()) return fail(EINVAL);
      const std::uint32_t index = b->index;
      std::memset(b, 0, sizeof(*b));
      b->index = index;
      b->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      b->memory = V4L2_MEMORY_MMAP;
      b->length = static_cast<std::uint32_t>(buffers_[index]->bytes.size());
      b->m.offset = static_cast<std::uint32_t>(index * kOffsetStep);
      b->flags = script_.timestamp_flags | (buffers_[index]->queued ? V4L2_BUF_FLAG_QUEUED : 0u);
      return 0;
    }
    case VIDIOC_QBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (fd != owner_fd_ || b->index >= buffers_.size() || buffers_[b->index]->queued) return fail(EINVAL);
      buffers_[b->index]->queued = true;
      queue_.push_back(b->index);
      return 0;
    }
    case VIDIOC_DQBUF:
      if (fd != owner_fd_) return fail(EINVAL);
      return dequeue_locked(arg);
    case VIDIOC_STREAMON:
      if (fd != owner_fd_ || buffers_.empty()) return fail(EINVAL);
      if (!streaming_) {
        streaming_ = true;
        stream_start_ns_ = monotonic_now_ns();
        next_sequence_ = 0;
        delivered_in_stream_ = 0;
        ++stream_starts_;
      }
      return 0;
    case VIDIOC_STREAMOFF:
      if (fd != owner_fd_) return fail(EINVAL);
      streaming_ = false;
      queue_.clear();
      for (auto& b : buffers_) b->queued = false;
      return 0;
    case VIDIOC_ENUM_FMT: {
      auto* f = static_cast<v4l2_fmtdesc*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || f->index >= script_.formats.size()) return fail(EINVAL);
      const PixelFormat pf = script_.formats[f->index];
      f->pixelformat = fourcc(pf);
      copy_name(f->description, sizeof(f->description), pf == PixelFormat::YUYV ? "YUYV 4:2:2" : "8-bit Greyscale");
      return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
      auto* s = static_cast<v4l2_frmsizeenum*>(arg);
      auto pf = from_fourcc(s->pixel_format);
      if (!pf || !std::count(script_.formats.begin(), script_.formats.end(), *pf) || s->index > 1) return fail(EINVAL);
      s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
      s->discrete.width = s->index == 0 ? 320 : 640;
      s->discrete.height = s->index == 0 ? 240 : 480;
      return 0;
    }
    default:
      return fail(ENOTTY);
  }
}

void* FakeV4l2Device::mmap(std::size_t length, int /*prot*/, int /*flags*/, int fd, off_t offset) {
  std::lock_guard lock(mutex_);
  const auto index = static_cast<std::size_t>(offset / kOffsetStep);
  if (fd != owner_fd_ || offset % kOffsetStep != 0 || index >= buffers_.size() ||
      length > buffers_[index]->bytes.size()) {
    errno = EINVAL;
    return MAP_FAILED;
  }
  ++buffers_[index]->mappings;
  return buffers_[index]->bytes.data();
}

int FakeV4l2Device::munmap(void* address, std::size_t /*length*/) {
  std::lock_guard lock(mutex_);
  for (auto& b : buffers_) {
    if (b->bytes.data() == address && b->mappings > 0) {
      --b->mappings;
      return 0;
    }
  }
  for (auto it = retired_.begin(); it != retired_.end(); ++it) {
    if ((*it)->bytes.data() == address && (*it)->mappings > 0) {
      if (--(*it)->mappings == 0) retired_.erase(it);
      return 0;
    }
  }
  return fail(EINVAL);
}

int FakeV4l2Device::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  const std::int64_t start = monotonic_now_ns();
  std::vector<pollfd> real;
  std::vector<nfds_t> real_index;
  for (;;) {
    int ready = 0;
    real.clear();
    real_index.clear();
    std::int64_t next_frame = -1;
    {
      std::lock_guard lock(mutex_);
      for (nfds_t i = 0; i < count; ++i) {
        fds[i].revents = 0;
        if (!is_fake_fd(fds[i].fd)) {
          real.push_back(fds[i]);
          real_index.push_back(i);
          continue;
        }
        if (!fds_.count(fds[i].fd)) {
          fds[i].revents = POLLNVAL;
        } else if (unplugged_) {
          fds[i].revents = POLLERR | POLLHUP;
        } else if (pollerr_pending_) {
          pollerr_pending_ = false;
          pollerr_done_ = true;
          fds[i].revents = POLLERR;
        } else if (frame_ready_locked()) {
          fds[i].revents = static_cast<short>(fds[i].events & POLLIN);
        } else if (script_.paced && streaming_) {
          next_frame = next_frame_time_locked();
        }
        if (fds[i].revents) ++ready;
      }
    }
    if (!real.empty() && ::poll(real.data(), real.size(), 0) > 0) {
      for (std::size_t k = 0; k < real.size(); ++k) {
        fds[real_index[k]].revents = real[k].revents;
        if (real[k].revents) ++ready;
      }
    }
    const std::int64_t elapsed_ms = (monotonic_now_ns() - start) / 1'000'000;
    if (ready > 0 || timeout_ms == 0 || (timeout_ms > 0 && elapsed_ms >= timeout_ms)) return ready;
    // Nothing yet: sleep briefly on the real descriptors (a wake-up eventfd
    // ends the sleep at once), then look again.
    std::int64_t wait_ms = 2;
    if (timeout_ms > 0) wait_ms = std::min<std::int64_t>(wait_ms, timeout_ms - elapsed_ms);
    if (next_frame >= 0) wait_ms = std::min<std::int64_t>(wait_ms, std::max<std::int64_t>((next_frame - monotonic_now_ns()) / 1'000'000, 0));
    ::poll(real.data(), real.size(), static_cast<int>(std::max<std::int64_t>(wait_ms, 0)));
  }
}

int FakeV4l2Device::open_fds() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(fds_.size());
}
int FakeV4l2Device::mapped_buffers() const {
  std::lock_guard lock(mutex_);
  int n = 0;
  for (const auto& b : buffers_) n += b->mappings;
  for (const auto& b : retired_) n += b->mappings;
  return n;
}
int FakeV4l2Device::queued_buffers() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(queue_.size());
}
std::uint64_t FakeV4l2Device::frames_delivered() const {
  std::lock_guard lock(mutex_);
  return delivered_total_;
}
std::uint64_t FakeV4l2Device::stream_starts() const {
  std::lock_guard lock(mutex_);
  return stream_starts_;
}
std::map<std::uint32_t, std::int32_t> FakeV4l2Device::controls() const {
  std::lock_guard lock(mutex_);
  return controls_;
}
double FakeV4l2Device::frame_rate() const {
  std::lock_guard lock(mutex_);
  return static_cast<double>(fps_den_) / fps_num_;
}
bool FakeV4l2Device::unplugged() const {
  std::lock_guard lock(mutex_);
  return unplugged_;
}

}  // namespace spinewatch
