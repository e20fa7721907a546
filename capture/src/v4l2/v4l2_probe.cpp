#include "spinewatch/capture/v4l2_probe.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace spinewatch {
namespace {

std::string text(const std::uint8_t* s, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(s), strnlen(reinterpret_cast<const char*>(s), size));
}

std::string fourcc_text(std::uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((code >> (8 * i)) & 0xff);
    if (c != ' ') s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

std::vector<std::string> frame_sizes(V4l2Device& device, int fd, std::uint32_t pixel_format) {
  std::vector<std::string> sizes;
  for (std::uint32_t i = 0; i < 64; ++i) {
    v4l2_frmsizeenum s{};
    s.index = i;
    s.pixel_format = pixel_format;
    if (device.ioctl(fd, VIDIOC_ENUM_FRAMESIZES, &s) < 0) break;
    if (s.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      sizes.push_back(fmt::format("{}x{}", s.discrete.width, s.discrete.height));
      continue;
    }
    const auto& w = s.stepwise;
    sizes.push_back(fmt::format("{}x{}-{}x{} step {}x{}", w.min_width, w.min_height, w.max_width, w.max_height,
                                w.step_width, w.step_height));
    break;  // stepwise and continuous ranges come as one entry
  }
  return sizes;
}

class ProbeFd {  // closes the node however the probe ends
 public:
  ProbeFd(V4l2Device& device, int fd) : device_(device), fd_(fd) {}
  ~ProbeFd() {
    if (fd_ >= 0) device_.close(fd_);
  }
  ProbeFd(const ProbeFd&) = delete;
  ProbeFd& operator=(const ProbeFd&) = delete;

 private:
  V4l2Device& device_;
  int fd_;
};

}  // namespace

Result<V4l2DeviceInfo> probe_v4l2_device(V4l2Device& device, const std::string& path) {
  const int fd = device.open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Error{fmt::format("{}: cannot open: {}", path, std::strerror(errno))};
  ProbeFd guard(device, fd);
  v4l2_capability cap{};
  if (device.ioctl(fd, VIDIOC_QUERYCAP, &cap) < 0) {
    return Error{fmt::format("{}: not a V4L2 device (VIDIOC_QUERYCAP: {})", path, std::strerror(errno))};
  }
  V4l2DeviceInfo info;
  info.path = path;
  info.driver = text(cap.driver, sizeof cap.driver);
  info.card = text(cap.card, sizeof cap.card);
  info.bus = text(cap.bus_info, sizeof cap.bus_info);
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  info.capture = caps & V4L2_CAP_VIDEO_CAPTURE;
  info.streaming = caps & V4L2_CAP_STREAMING;
  if (!info.capture) return info;
  for (std::uint32_t i = 0; i < 64; ++i) {
    v4l2_fmtdesc f{};
    f.index = i;
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (device.ioctl(fd, VIDIOC_ENUM_FMT, &f) < 0) break;
    info.formats.push_back({fourcc_text(f.pixelformat), text(f.description, sizeof f.description),
                            frame_sizes(device, fd, f.pixelformat)});
  }
  return info;
}

std::vector<std::string> list_video_nodes(const std::filesystem::path& dev) {
  std::vector<std::pair<int, std::string>> nodes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dev, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("video", 0) != 0 || name.size() == 5) continue;
    const std::string number = name.substr(5);
    if (!std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    nodes.emplace_back(std::stoi(number), entry.path().string());
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<std::string> paths;
  for (auto& n : nodes) paths.push_back(std::move(n.second));
  return paths;
}

}  // namespace spinewatch
