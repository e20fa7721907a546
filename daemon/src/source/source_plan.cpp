#include "source/source_plan.hpp"

#include <cstdlib>

#include <fmt/format.h>

namespace spinewatch {
namespace {

bool is_device_node(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_character_file(path, ec);
}

Result<SourcePlan> embedded(const Config& config, std::string why) {
  std::vector<std::string> tried;
  for (const auto& dir : embedded_recording_dirs()) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(dir / "recording.json", ec)) {
      return SourcePlan{SourcePlan::Kind::Recording, dir, true, config.cameras.replay == ReplayPace::Paced, std::move(why)};
    }
    tried.push_back(dir.string());
  }
  return Error{fmt::format("{}, but the embedded phantom recording is in none of: {} (set SPINEWATCH_DATA_DIR)", why,
                           fmt::join(tried, ", "))};
}

}  // namespace

std::vector<std::filesystem::path> embedded_recording_dirs() {
  std::vector<std::filesystem::path> dirs;
  if (const char* data = std::getenv("SPINEWATCH_DATA_DIR"); data != nullptr && *data != '\0')
    dirs.emplace_back(std::filesystem::path(data) / "demo");
  dirs.emplace_back(SPINEWATCH_BUILD_DATA_DIR "/demo");
  dirs.emplace_back(SPINEWATCH_INSTALL_DATA_DIR "/demo");
  return dirs;
}

Result<SourcePlan> plan_source(const Config& config) {
  const auto& cameras = config.cameras;
  const bool paced = cameras.replay == ReplayPace::Paced;
  switch (cameras.source) {
    case CameraSource::V4l2:
    case CameraSource::Libcamera:
      return SourcePlan{SourcePlan::Kind::Cameras, {}, false, true,
                        fmt::format("cameras.source = \"{}\"", to_string(cameras.source))};
    case CameraSource::Recording:
      if (cameras.recording.empty()) return embedded(config, "cameras.source = \"recording\" with cameras.recording = \"\"");
      return SourcePlan{SourcePlan::Kind::Recording, cameras.recording, false, paced, "cameras.source = \"recording\""};
    case CameraSource::Auto:
      break;
  }
  if (is_device_node(cameras.frontal) && is_device_node(cameras.lateral))
    return SourcePlan{SourcePlan::Kind::Cameras, {}, false, true,
                      fmt::format("cameras.source = \"auto\" and {} and {} exist", cameras.frontal, cameras.lateral)};
  const std::string why = fmt::format("cameras.source = \"auto\" and no camera at {} and {}", cameras.frontal, cameras.lateral);
  if (!cameras.recording.empty())
    return SourcePlan{SourcePlan::Kind::Recording, cameras.recording, false, paced, why};
  return embedded(config, why);
}

}  // namespace spinewatch
