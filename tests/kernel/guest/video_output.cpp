#include "video_output.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace spinewatch::kernel_test {
namespace {

int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do {
    rc = ::ioctl(fd, request, arg);
  } while (rc < 0 && errno == EINTR);
  return rc;
}

Error ioctl_error(const std::string& path, const char* what) {
  return Error{fmt::format("{}: {}: {}", path, what, std::strerror(errno))};
}

}  // namespace

Result<std::unique_ptr<VideoOutput>> VideoOutput::open(const std::string& path, FrameFormat format) {
  std::unique_ptr<VideoOutput> out(new VideoOutput);
  out->fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (out->fd_ < 0) return ioctl_error(path, "open");

  v4l2_format f{};
  f.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  f.fmt.pix.width = format.width;
  f.fmt.pix.height = format.height;
  f.fmt.pix.pixelformat = fourcc(format.pixel_format);
  f.fmt.pix.field = V4L2_FIELD_NONE;
  f.fmt.pix.bytesperline = format.bytesperline;
  if (xioctl(out->fd_, VIDIOC_S_FMT, &f) < 0) return ioctl_error(path, "VIDIOC_S_FMT");
  if (f.fmt.pix.width != format.width || f.fmt.pix.height != format.height ||
      f.fmt.pix.pixelformat != fourcc(format.pixel_format) || f.fmt.pix.field != V4L2_FIELD_NONE) {
    return Error{fmt::format("{}: the output took {}x{} field {} instead of {}", path, f.fmt.pix.width,
                             f.fmt.pix.height, f.fmt.pix.field, describe(format))};
  }
  out->format_ = FrameFormat{format.pixel_format, f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.bytesperline};
  out->image_.assign(out->format_.frame_bytes(), 0);

  v4l2_requestbuffers req{};
  req.count = 4;
  req.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(out->fd_, VIDIOC_REQBUFS, &req) < 0) return ioctl_error(path, "VIDIOC_REQBUFS");
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(out->fd_, VIDIOC_QUERYBUF, &buf) < 0) return ioctl_error(path, "VIDIOC_QUERYBUF");
    void* address = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, out->fd_, buf.m.offset);
    if (address == MAP_FAILED) return ioctl_error(path, "mmap");
    out->buffers_.push_back({address, buf.length});
    if (buf.length < out->format_.frame_bytes()) return Error{fmt::format("{}: buffer {} too small", path, i)};
  }
  return out;
}

VideoOutput::~VideoOutput() {
  stop_.store(true);
  if (feeder_.joinable()) feeder_.join();
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
  }
  for (const auto& b : buffers_) ::munmap(b.address, b.length);
  if (fd_ >= 0) ::close(fd_);
}

void VideoOutput::show(std::span<const std::uint8_t> image) {
  std::lock_guard lock(mutex_);
  std::copy_n(image.begin(), std::min(image.size(), image_.size()), image_.begin());
}

Status VideoOutput::queue(std::uint32_t index) {
  {
    std::lock_guard lock(mutex_);
    std::memcpy(buffers_[index].address, image_.data(), image_.size());
  }
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = index;
  buf.bytesused = static_cast<std::uint32_t>(image_.size());
  buf.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) return Error{fmt::format("VIDIOC_QBUF {}: {}", index, std::strerror(errno))};
  fed_.fetch_add(1);
  return Ok{};
}

Status VideoOutput::start() {
  for (std::uint32_t i = 0; i < buffers_.size(); ++i) {
    if (auto s = queue(i); !s) return s;
  }
  int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0) return Error{fmt::format("VIDIOC_STREAMON: {}", std::strerror(errno))};
  streaming_ = true;
  feeder_ = std::thread([this] { feed(); });
  return Ok{};
}

void VideoOutput::feed() {
  while (!stop_.load()) {
    pollfd pfd{fd_, POLLOUT, 0};
    if (::poll(&pfd, 1, 20) <= 0 || !(pfd.revents & POLLOUT)) continue;
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    buf.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) continue;  // EAGAIN: not done with it yet
    if (!queue(buf.index)) return;  // the test sees the capture side stall
  }
}

}  // namespace spinewatch::kernel_test
