#pragma once
// recording.json: parsing with one message per problem (naming the file and
// the field), and the writer's side of the same format.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spinewatch/capture/recording.hpp"
#include "spinewatch/frames/frame.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::recording_detail {

// What recording.json declares, before the .raw files are checked against it.
struct DeclaredRecording {
  FrameFormat format;
  double fps = 0.0;
  // nullopt: no "frames" entry for the view (frame i then has seq i, t = i / fps).
  std::optional<std::vector<FrameInfo>> frames[2];
  nlohmann::json subject;
  std::string notes;
};

// Upper bounds that keep sizes far from overflow; no camera comes near them.
inline constexpr std::int64_t kMaxDimension = 16384;
inline constexpr std::int64_t kMaxBytesPerLine = 1 << 20;
inline constexpr double kMaxFps = 1000.0;

Result<DeclaredRecording> parse_recording_json(const std::filesystem::path& file);

// The text of recording.json for `info`: one key a line, one frame a line.
std::string format_recording_json(const RecordingInfo& info);

// seq i, t_ns = round(i · 1e9 / fps): the metadata of a recording without "frames".
std::vector<FrameInfo> default_frame_infos(std::size_t count, double fps);

}  // namespace spinewatch::recording_detail
