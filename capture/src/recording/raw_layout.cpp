#include "raw_layout.hpp"

#include <vector>

#include <fmt/format.h>

namespace spinewatch::recording_detail {
namespace {

std::string truncation_warning(const std::filesystem::path& raw, std::uintmax_t size, std::uintmax_t frame_bytes) {
  return fmt::format("{}: {} bytes: truncated last frame dropped ({} of {} bytes)", raw.string(), size,
                     size % frame_bytes, frame_bytes);
}

// The frame sizes a recording is plausibly mistaken for: the same size with
// packed rows, or the other pixel format.
std::vector<FrameFormat> plausible_alternatives(const FrameFormat& format) {
  std::vector<FrameFormat> out;
  for (PixelFormat pf : {PixelFormat::YUYV, PixelFormat::GREY}) {
    const auto alt = FrameFormat::packed(pf, format.width, format.height);
    if (alt.frame_bytes() != format.frame_bytes()) out.push_back(alt);
  }
  return out;
}

Result<RawLayout> fit_listed(const std::filesystem::path& raw, std::uintmax_t size, std::uintmax_t frame_bytes,
                             std::size_t listed, const std::string& listed_by) {
  const auto whole = size / frame_bytes;
  const auto partial = size % frame_bytes;
  if (whole == listed && partial == 0) return RawLayout{listed, std::nullopt};
  if (listed > 0 && whole == listed - 1 && partial > 0)
    return RawLayout{listed - 1, truncation_warning(raw, size, frame_bytes)};
  if (partial != 0)
    return Error{fmt::format("{}: {} bytes is not a whole number of {}-byte frames ({} lists {} frames)",
                             raw.string(), size, frame_bytes, listed_by, listed)};
  return Error{fmt::format("{}: holds {} frames of {} bytes but {} lists {} frames", raw.string(), whole,
                           frame_bytes, listed_by, listed)};
}

Result<RawLayout> fit_unlisted(const std::filesystem::path& raw, std::uintmax_t size, const FrameFormat& format) {
  const std::uintmax_t frame_bytes = format.frame_bytes();
  const auto whole = size / frame_bytes;
  const auto partial = size % frame_bytes;
  if (partial == 0 || whole == 0) return RawLayout{whole, std::nullopt};
  for (const auto& alt : plausible_alternatives(format)) {
    if (size % alt.frame_bytes() != 0) continue;
    return Error{fmt::format("{}: {} bytes is not a whole number of {}-byte frames ({}), but exactly {} frames of "
                             "{} ({} bytes): check pixel_format and bytesperline in recording.json",
                             raw.string(), size, frame_bytes, describe(format), size / alt.frame_bytes(),
                             describe(alt), alt.frame_bytes())};
  }
  return RawLayout{whole, truncation_warning(raw, size, frame_bytes)};
}

}  // namespace

Result<RawLayout> fit_raw_file(const std::filesystem::path& raw, std::uintmax_t size, const FrameFormat& format,
                               std::optional<std::size_t> listed, const std::string& listed_by) {
  auto layout = listed ? fit_listed(raw, size, format.frame_bytes(), *listed, listed_by)
                       : fit_unlisted(raw, size, format);
  if (layout && layout->frames == 0)
    return Error{fmt::format("{}: empty stream: {} bytes, not one whole {}-byte frame ({})", raw.string(), size,
                             format.frame_bytes(), describe(format))};
  return layout;
}

}  // namespace spinewatch::recording_detail
