#pragma once
// The one symbol spinewatch-media.so exports, and what it returns: the
// loader (media_files.cpp) and the module (opencv_media.cpp) are built
// from the same tree in the same build, so the table needs no version
// beyond a size check.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "spinewatch/media/media_files.hpp"

namespace spinewatch::media {

struct ModuleFunctions {
  std::size_t size = sizeof(ModuleFunctions);
  std::unique_ptr<VideoReader> (*open_video)(const std::string& path);
  cv::Mat (*read_image)(const std::string& path, int flags);
  bool (*write_image)(const std::string& path, const cv::Mat& image, const std::vector<int>& params);
};

inline constexpr const char* kModuleEntry = "spinewatch_media_functions";

}  // namespace spinewatch::media

extern "C" const spinewatch::media::ModuleFunctions* spinewatch_media_functions();
