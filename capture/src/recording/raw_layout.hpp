#pragma once
// How many frames a .raw file holds: the rule for a truncated last frame
// versus a size that is simply wrong (docs/recording.md).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "spinewatch/frames/pixel_format.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::recording_detail {

struct RawLayout {
  std::size_t frames = 0;          // whole frames to replay (the partial one excluded)
  std::optional<std::string> warning;  // set when a truncated last frame is dropped
};

// `listed`: the number of frames recording.json lists for this stream, when it
// lists any; `listed_by` names that list in messages ("rec/recording.json frames.frontal").
Result<RawLayout> fit_raw_file(const std::filesystem::path& raw, std::uintmax_t size, const FrameFormat& format,
                               std::optional<std::size_t> listed, const std::string& listed_by);

}  // namespace spinewatch::recording_detail
