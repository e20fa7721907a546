#include <gtest/gtest.h>

#include "spinewatch/frames/frame.hpp"

namespace spinewatch {
namespace {

TEST(PixelFormat, NamesAndFourccRoundTrip) {
  for (auto f : {PixelFormat::YUYV, PixelFormat::GREY}) {
    EXPECT_EQ(parse_pixel_format(to_string(f)), f);
    EXPECT_EQ(from_fourcc(fourcc(f)), f);
  }
  EXPECT_EQ(fourcc(PixelFormat::YUYV), 0x56595559u);  // V4L2_PIX_FMT_YUYV
  EXPECT_EQ(fourcc(PixelFormat::GREY), 0x59455247u);  // V4L2_PIX_FMT_GREY
  EXPECT_FALSE(parse_pixel_format("MJPG"));
}

TEST(FrameFormat, FrameBytesHonoursBytesPerLine) {
  FrameFormat f{PixelFormat::YUYV, 320, 240, 704};
  EXPECT_EQ(f.frame_bytes(), 704u * 240u);
  EXPECT_EQ(f.min_bytesperline(), 640u);
  EXPECT_EQ(FrameFormat::packed(PixelFormat::GREY, 320, 240).bytesperline, 320u);
}

TEST(Frame, LumaViewOfYuyvSkipsChroma) {
  FrameFormat f{PixelFormat::YUYV, 4, 2, 10};  // 2 padding bytes a row
  std::vector<std::uint8_t> bytes = {10, 128, 11, 128, 12, 128, 13, 128, 0, 0,
                                     20, 128, 21, 128, 22, 128, 23, 128, 0, 0};
  Frame frame = Frame::owning(f, {7, 1000}, std::move(bytes));
  const LumaView y = frame.luma();
  EXPECT_EQ(y.at(0, 0), 10);
  EXPECT_EQ(y.at(3, 0), 13);
  EXPECT_EQ(y.at(0, 1), 20);
  EXPECT_EQ(y.at(3, 1), 23);
  EXPECT_EQ(frame.sequence(), 7u);
  EXPECT_EQ(frame.timestamp_ns(), 1000);
}

TEST(Frame, CopiesShareStorageAndReleaseItWithTheLastCopy) {
  struct Lease {
    Lease(bool* flag, std::size_t size) : released(flag), bytes(size, 7) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { *released = true; }
    bool* released;
    std::vector<std::uint8_t> bytes;
  };
  bool released = false;
  {
    auto lease = std::make_shared<Lease>(&released, std::size_t{320 * 240});
    std::span<const std::uint8_t> view(lease->bytes);
    Frame a(FrameFormat::packed(PixelFormat::GREY, 320, 240), {}, lease, view);
    lease.reset();
    Frame b = a;
    EXPECT_EQ(a.bytes().data(), b.bytes().data());
    a = Frame();
    EXPECT_FALSE(released);
    EXPECT_EQ(b.luma().at(5, 5), 7);
  }
  EXPECT_TRUE(released);
}

}  // namespace
}  // namespace spinewatch
