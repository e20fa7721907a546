#include "spinewatch/frames/frame.hpp"

#include <utility>

namespace spinewatch {

Frame::Frame(FrameFormat format, FrameInfo info, std::shared_ptr<const void> owner,
             std::span<const std::uint8_t> bytes)
    : format_(format), info_(info), owner_(std::move(owner)), bytes_(bytes) {}

Frame Frame::copy_of(FrameFormat format, FrameInfo info, std::span<const std::uint8_t> bytes) {
  return owning(format, info, std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
}

Frame Frame::owning(FrameFormat format, FrameInfo info, std::vector<std::uint8_t> bytes) {
  auto storage = std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes));
  std::span<const std::uint8_t> view(*storage);
  return Frame(format, info, std::move(storage), view);
}

LumaView Frame::luma() const {
  LumaView v;
  v.data = bytes_.data();
  v.width = static_cast<int>(format_.width);
  v.height = static_cast<int>(format_.height);
  v.stride = format_.bytesperline;
  v.step = format_.pixel_format == PixelFormat::YUYV ? 2 : 1;
  return v;
}

}  // namespace spinewatch
