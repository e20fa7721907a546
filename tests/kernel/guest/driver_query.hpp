#pragma once
// Asks the driver directly (not through our V4L2 source) what it runs at,
// so that tests compare our figures with the kernel's, not with themselves.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <optional>
#include <string>

namespace spinewatch::kernel_test {

// Frames per second from VIDIOC_G_PARM on a capture device.
inline std::optional<double> driver_fps(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  const int rc = ::ioctl(fd, VIDIOC_G_PARM, &parm);
  ::close(fd);
  const auto& tpf = parm.parm.capture.timeperframe;
  if (rc < 0 || tpf.numerator == 0) return std::nullopt;
  return static_cast<double>(tpf.denominator) / tpf.numerator;
}

}  // namespace spinewatch::kernel_test
