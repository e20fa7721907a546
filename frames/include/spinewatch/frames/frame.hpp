#pragma once
// A captured image and its metadata. Pixel storage is owned through a
// shared handle: a recording frame owns a heap buffer, a V4L2 frame owns a
// lease on an mmap buffer that is queued back to the driver when the last
// copy of the Frame goes away (never before).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "spinewatch/frames/pixel_format.hpp"

namespace spinewatch {

struct FrameInfo {
  std::uint64_t sequence = 0;      // driver sequence number (or recording index)
  std::int64_t timestamp_ns = 0;   // CLOCK_MONOTONIC, or recording time
};

// A read-only view of the luma (Y) plane: GREY rows are consecutive bytes,
// YUYV rows have Y at every other byte. No copy is made.
struct LumaView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // bytes from one row to the next
  int step = 1;               // bytes from one pixel to the next

  const std::uint8_t* row(int y) const { return data + y * stride; }
  std::uint8_t at(int x, int y) const { return row(y)[x * step]; }
};

class Frame {
 public:
  Frame() = default;
  // `owner` keeps `bytes` alive; it may be any object (buffer lease, vector).
  Frame(FrameFormat format, FrameInfo info, std::shared_ptr<const void> owner,
        std::span<const std::uint8_t> bytes);

  // A frame that owns a copy of `bytes`.
  static Frame copy_of(FrameFormat format, FrameInfo info, std::span<const std::uint8_t> bytes);
  // A frame that takes ownership of `bytes`.
  static Frame owning(FrameFormat format, FrameInfo info, std::vector<std::uint8_t> bytes);

  bool empty() const { return bytes_.empty(); }
  const FrameFormat& format() const { return format_; }
  const FrameInfo& info() const { return info_; }
  std::uint64_t sequence() const { return info_.sequence; }
  std::int64_t timestamp_ns() const { return info_.timestamp_ns; }
  std::span<const std::uint8_t> bytes() const { return bytes_; }
  LumaView luma() const;

 private:
  FrameFormat format_{};
  FrameInfo info_{};
  std::shared_ptr<const void> owner_;
  std::span<const std::uint8_t> bytes_;
};

}  // namespace spinewatch
