#pragma once
// What `spinewatch devices` reports about a V4L2 node: identity, and the
// capture formats with their frame sizes.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spinewatch/capture/v4l2_device.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch {

struct V4l2FormatInfo {
  std::string fourcc;       // "YUYV"
  std::string description;  // the driver's
  std::vector<std::string> sizes;  // "320x240", or "16x16-1920x1080 step 2x2"
};

struct V4l2DeviceInfo {
  std::string path;
  std::string driver;
  std::string card;
  std::string bus;
  bool capture = false;    // V4L2_CAP_VIDEO_CAPTURE
  bool streaming = false;  // V4L2_CAP_STREAMING
  std::vector<V4l2FormatInfo> formats;
};

Result<V4l2DeviceInfo> probe_v4l2_device(V4l2Device& device, const std::string& path);
// /dev/video* under `dev`, in numeric order.
std::vector<std::string> list_video_nodes(const std::filesystem::path& dev = "/dev");

}  // namespace spinewatch
