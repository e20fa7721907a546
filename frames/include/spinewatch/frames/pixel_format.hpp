#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace spinewatch {

// The formats a recording or a camera may deliver (docs/interfaces.md §2).
enum class PixelFormat : std::uint8_t { YUYV, GREY };

std::string_view to_string(PixelFormat format);
std::optional<PixelFormat> parse_pixel_format(std::string_view name);
// V4L2 fourcc of the format (V4L2_PIX_FMT_YUYV / V4L2_PIX_FMT_GREY).
std::uint32_t fourcc(PixelFormat format);
std::optional<PixelFormat> from_fourcc(std::uint32_t code);
unsigned bytes_per_pixel(PixelFormat format);

struct FrameFormat {
  PixelFormat pixel_format = PixelFormat::YUYV;
  std::uint32_t width = 320;
  std::uint32_t height = 240;
  std::uint32_t bytesperline = 640;  // may exceed width × bytes per pixel

  std::size_t frame_bytes() const { return std::size_t{bytesperline} * height; }
  std::uint32_t min_bytesperline() const { return width * bytes_per_pixel(pixel_format); }
  static FrameFormat packed(PixelFormat format, std::uint32_t width, std::uint32_t height) {
    return {format, width, height, width * bytes_per_pixel(format)};
  }
  bool operator==(const FrameFormat&) const = default;
};

std::string describe(const FrameFormat& format);  // "YUYV 320x240 bpl 640"

}  // namespace spinewatch
