#include "stream_session.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace spinewatch::v4l2 {
namespace {
constexpr unsigned kMinBuffers = 2;  // fewer cannot stream without dropping every other frame

std::string fourcc_text(std::uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((code >> (8 * i)) & 0xff);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}
}  // namespace

Result<std::shared_ptr<StreamSession>> StreamSession::open(std::shared_ptr<V4l2Device> device,
                                                          const V4l2CameraOptions& options, const std::string& name) {
  std::shared_ptr<StreamSession> session(new StreamSession(std::move(device), name));
  const int fd = session->device_->open(options.path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Error{fmt::format("{}: cannot open {}: {}", name, options.path, std::strerror(errno))};
  session->fd_ = DeviceFd(session->device_, fd);
  auto configured = session->configure(options);
  if (!configured) return configured.error();
  return session;
}

StreamSession::~StreamSession() { shutdown(); }

Status StreamSession::configure(const V4l2CameraOptions& options) {
  v4l2_capability cap{};
  if (xioctl(VIDIOC_QUERYCAP, &cap) < 0) {
    return Error{fmt::format("{}: {} is not a V4L2 device (VIDIOC_QUERYCAP: {})", name_, options.path,
                             std::strerror(errno))};
  }
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  const std::string card(reinterpret_cast<const char*>(cap.card), strnlen(reinterpret_cast<const char*>(cap.card), sizeof(cap.card)));
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) {
    return Error{fmt::format("{}: {} ({}) is not a video capture device", name_, options.path, card)};
  }
  if (!(caps & V4L2_CAP_STREAMING)) {
    return Error{fmt::format("{}: {} ({}) does not support streaming I/O", name_, options.path, card)};
  }
  if (auto s = set_format(options); !s) return s;
  set_frame_rate(options.fps);
  if (options.exposure_us > 0) {
    set_control(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL, "manual exposure");
    // V4L2_CID_EXPOSURE_ABSOLUTE counts 100 µs units.
    set_control(V4L2_CID_EXPOSURE_ABSOLUTE, std::max(1, static_cast<int>(std::lround(options.exposure_us / 100.0))),
                "exposure");
  }
  if (options.gain >= 0) set_control(V4L2_CID_GAIN, options.gain, "gain");
  if (auto s = map_buffers(std::max(options.buffers, 4u)); !s) return s;
  return start_streaming();
}

Status StreamSession::set_format(const V4l2CameraOptions& options) {
  v4l2_format f{};
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  f.fmt.pix.width = options.width;
  f.fmt.pix.height = options.height;
  f.fmt.pix.pixelformat = fourcc(options.pixel_format);
  f.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(VIDIOC_S_FMT, &f) < 0) {
    return Error{fmt::format("{}: cannot set format {} {}x{} (VIDIOC_S_FMT: {})", name_,
                             to_string(options.pixel_format), options.width, options.height, std::strerror(errno))};
  }
  const auto got = from_fourcc(f.fmt.pix.pixelformat);
  if (!got || *got != options.pixel_format) {
    return Error{fmt::format("{}: the driver offers {} instead of {}", name_, fourcc_text(f.fmt.pix.pixelformat),
                             to_string(options.pixel_format))};
  }
  if (f.fmt.pix.width != options.width || f.fmt.pix.height != options.height) {
    spdlog::warn("{}: the driver chose {}x{} instead of {}x{}", name_, f.fmt.pix.width, f.fmt.pix.height,
                 options.width, options.height);
  }
  format_ = FrameFormat{*got, f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.bytesperline};
  // Some drivers leave bytesperline 0 for packed formats.
  if (format_.bytesperline < format_.min_bytesperline()) format_.bytesperline = format_.min_bytesperline();
  if (f.fmt.pix.sizeimage != 0 && f.fmt.pix.sizeimage < format_.frame_bytes()) {
    return Error{fmt::format("{}: the driver's sizeimage {} is smaller than bytesperline {} × height {}", name_,
                             f.fmt.pix.sizeimage, format_.bytesperline, format_.height)};
  }
  return Ok{};
}

void StreamSession::set_frame_rate(double fps) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = 1000;
  parm.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(std::lround(fps * 1000.0));
  if (xioctl(VIDIOC_S_PARM, &parm) < 0 || !(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
    spdlog::warn("{}: the driver does not take a frame rate; it runs at its own (or the trigger's)", name_);
    fps_ = fps;
    return;
  }
  const auto& tpf = parm.parm.capture.timeperframe;
  fps_ = tpf.numerator ? static_cast<double>(tpf.denominator) / tpf.numerator : fps;
  if (std::abs(fps_ - fps) > 0.01) spdlog::warn("{}: the driver runs at {:.3f} fps instead of {:.3f}", name_, fps_, fps);
}

void StreamSession::set_control(std::uint32_t id, std::int32_t value, const char* what) {
  v4l2_control control{id, value};
  if (xioctl(VIDIOC_S_CTRL, &control) < 0) {
    spdlog::warn("{}: cannot set {} to {} ({}); left to the driver", name_, what, value, std::strerror(errno));
  }
}

Status StreamSession::map_buffers(unsigned count) {
  v4l2_requestbuffers req{};
  req.count = count;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_REQBUFS, &req) < 0) {
    return Error{fmt::format("{}: cannot allocate mmap buffers (VIDIOC_REQBUFS: {})", name_, std::strerror(errno))};
  }
  if (req.count < kMinBuffers) return Error{fmt::format("{}: the driver gave only {} buffer(s)", name_, req.count)};
  if (req.count < count) spdlog::warn("{}: the driver gave {} buffers, not {}", name_, req.count, count);
  buffers_.reserve(req.count);
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(VIDIOC_QUERYBUF, &buf) < 0) {
      return Error{fmt::format("{}: VIDIOC_QUERYBUF {}: {}", name_, i, std::strerror(errno))};
    }
    if (buf.length < format_.frame_bytes()) {
      return Error{fmt::format("{}: buffer {} holds {} bytes, a frame needs {}", name_, i, buf.length,
                               format_.frame_bytes())};
    }
    void* address = device_->mmap(buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_.get(), buf.m.offset);
    if (address == MAP_FAILED) return Error{fmt::format("{}: mmap of buffer {}: {}", name_, i, std::strerror(errno))};
    buffers_.emplace_back(device_, address, buf.length);
  }
  return Ok{};
}

Status StreamSession::start_streaming() {
  for (std::uint32_t i = 0; i < buffers_.size(); ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(VIDIOC_QBUF, &buf) < 0) return Error{fmt::format("{}: VIDIOC_QBUF {}: {}", name_, i, std::strerror(errno))};
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(VIDIOC_STREAMON, &type) < 0) {
    return Error{fmt::format("{}: cannot start streaming (VIDIOC_STREAMON: {})", name_, std::strerror(errno))};
  }
  std::lock_guard lock(mutex_);
  live_ = true;
  return Ok{};
}

int StreamSession::dequeue(Dequeued& out) {
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_DQBUF, &buf) < 0) return errno;
  if (buf.index >= buffers_.size()) return EIO;
  out.index = buf.index;
  out.sequence = buf.sequence;
  out.flags = buf.flags;
  out.bytesused = buf.bytesused;
  out.timestamp_ns = static_cast<std::int64_t>(buf.timestamp.tv_sec) * 1'000'000'000 +
                     static_cast<std::int64_t>(buf.timestamp.tv_usec) * 1000;
  return 0;
}

std::span<const std::uint8_t> StreamSession::bytes(std::uint32_t index) const {
  return {buffers_[index].data(), format_.frame_bytes()};
}

void StreamSession::requeue(std::uint32_t index) {
  std::lock_guard lock(mutex_);
  if (!live_) return;
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = index;
  if (xioctl(VIDIOC_QBUF, &buf) < 0) spdlog::debug("{}: VIDIOC_QBUF {}: {}", name_, index, std::strerror(errno));
}

void StreamSession::shutdown() {
  std::lock_guard lock(mutex_);
  if (live_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(VIDIOC_STREAMOFF, &type);  // fails harmlessly on a device that is gone
    live_ = false;
  }
  // Closing frees the driver's queue; the mappings keep the memory of frames
  // still in use valid until their leases go.
  fd_.reset();
}

}  // namespace spinewatch::v4l2
