#include "spinewatch/frames/pixel_format.hpp"

#include <fmt/format.h>

namespace spinewatch {
namespace {
constexpr std::uint32_t make_fourcc(char a, char b, char c, char d) {
  return std::uint32_t(std::uint8_t(a)) | std::uint32_t(std::uint8_t(b)) << 8 |
         std::uint32_t(std::uint8_t(c)) << 16 | std::uint32_t(std::uint8_t(d)) << 24;
}
}  // namespace

std::string_view to_string(PixelFormat format) {
  switch (format) {
    case PixelFormat::YUYV: return "YUYV";
    case PixelFormat::GREY: return "GREY";
  }
  return "?";
}

std::optional<PixelFormat> parse_pixel_format(std::string_view name) {
  if (name == "YUYV") return PixelFormat::YUYV;
  if (name == "GREY") return PixelFormat::GREY;
  return std::nullopt;
}

std::uint32_t fourcc(PixelFormat format) {
  return format == PixelFormat::YUYV ? make_fourcc('Y', 'U', 'Y', 'V') : make_fourcc('G', 'R', 'E', 'Y');
}

std::optional<PixelFormat> from_fourcc(std::uint32_t code) {
  if (code == fourcc(PixelFormat::YUYV)) return PixelFormat::YUYV;
  if (code == fourcc(PixelFormat::GREY)) return PixelFormat::GREY;
  return std::nullopt;
}

unsigned bytes_per_pixel(PixelFormat format) { return format == PixelFormat::YUYV ? 2 : 1; }

std::string describe(const FrameFormat& f) {
  return fmt::format("{} {}x{} bpl {}", to_string(f.pixel_format), f.width, f.height, f.bytesperline);
}

}  // namespace spinewatch
