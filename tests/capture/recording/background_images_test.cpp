// The station's stored background as files (docs/interfaces.md §2): a colour
// background round-trips through its PNG as YUYV (luma and chroma within a
// level), a grey one stays grey, and files that cannot be a background are
// refused with their name and the problem.
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "spinewatch/capture/background_images.hpp"
#include "test_support.hpp"

namespace spinewatch {
namespace {

constexpr int kW = 64, kH = 48;

// A YUYV scene: a luma gradient, chroma that changes across the image
// (each pixel pair one U and V), within the colours an RGB PNG can hold.
SceneImage colour_scene(int seed) {
  SceneImage image{kW, kH, 2, std::vector<std::uint8_t>(2 * kW * kH)};
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::uint8_t* p = image.pixels.data() + 2 * (y * kW + x);
      p[0] = static_cast<std::uint8_t>(60 + 2 * x + y + seed);
      p[1] = static_cast<std::uint8_t>(x % 2 == 0 ? 118 + (x / 8) + seed : 140 - (y / 6));  // U, then V
    }
  return image;
}

TEST(BackgroundImages, ColourRoundTripsAsYuyvWithinALevel) {
  test::TempDir dir;
  BackgroundImages images{colour_scene(0), colour_scene(5)};
  ASSERT_TRUE(write_background_images(dir.path(), images));
  // A colour PNG, whose grey reading is the luma.
  const cv::Mat png = cv::imread((dir.path() / kBackgroundFiles[0]).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(png.channels(), 3);
  const cv::Mat grey = cv::imread((dir.path() / kBackgroundFiles[0]).string(), cv::IMREAD_GRAYSCALE);
  auto loaded = load_background_images(dir.path(), kW, kH);
  ASSERT_TRUE(loaded) << loaded.error().message;
  for (int v = 0; v < 2; ++v) {
    const SceneImage& in = v == 0 ? images.frontal : images.lateral;
    const SceneImage& out = v == 0 ? loaded->frontal : loaded->lateral;
    ASSERT_TRUE(out.colour());
    ASSERT_EQ(out.pixels.size(), in.pixels.size());
    int worst = 0;
    for (std::size_t i = 0; i < in.pixels.size(); ++i) worst = std::max(worst, std::abs(in.pixels[i] - out.pixels[i]));
    EXPECT_LE(worst, 1) << "view " << v;
  }
  int worst_grey = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      worst_grey = std::max(worst_grey, std::abs(grey.at<std::uint8_t>(y, x) - images.frontal.pixels[std::size_t(2 * (y * kW + x))]));
  EXPECT_LE(worst_grey, 1);
}

TEST(BackgroundImages, GreyStaysGrey) {
  test::TempDir dir;
  SceneImage grey{kW, kH, 1, std::vector<std::uint8_t>(kW * kH, 77)};
  ASSERT_TRUE(write_background_images(dir.path(), {grey, grey}));
  auto loaded = load_background_images(dir.path(), kW, kH);
  ASSERT_TRUE(loaded) << loaded.error().message;
  EXPECT_FALSE(loaded->frontal.colour());
  EXPECT_EQ(loaded->frontal.pixels, grey.pixels);
  EXPECT_EQ(loaded->frontal.view().step, 1);
}

TEST(BackgroundImages, RefusesWhatCannotBeABackground) {
  test::TempDir dir;
  const auto deep = dir.path() / "deep.png";
  ASSERT_TRUE(cv::imwrite(deep.string(), cv::Mat(kH, kW, CV_16U, cv::Scalar(1000))));
  const auto grey = dir.path() / "grey.png";
  ASSERT_TRUE(cv::imwrite(grey.string(), cv::Mat(kH, kW, CV_8U, cv::Scalar(90))));
  auto r = load_background_images(deep, grey);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, deep.string() + ": cannot be read as an 8-bit grey or colour image");
  r = load_background_images(grey, grey, 320, 240);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, grey.string() + ": 64x48 does not match the cameras' 320x240");
}

// A PNG whose header (checksum valid) declares 30000x30000 colour pixels:
// OpenCV sized its buffer from the header before decoding and asked for
// 2.7 GB (the background_png harness, given this file, reports the
// allocation). The size is read from the header and refused first now.
TEST(BackgroundImages, AHugeDeclaredSizeIsRefusedBeforeDecoding) {
  const auto huge = test::source_path("tests/fuzz/corpus/background_png/huge-declared-size.png");
  auto r = load_background_images(huge, huge);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, huge.string() + ": 30000x30000 is not a camera's size (1..4096 a side)");
  r = load_background_images(huge, huge, kW, kH);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, huge.string() + ": 30000x30000 does not match the cameras' 64x48");
}

// Written by another program (OpenCV's imgcodecs, an independent libpng
// user): an alpha channel is dropped, not blended, as a camera has none.
TEST(BackgroundImages, AnAlphaChannelIsDropped) {
  test::TempDir dir;
  const auto with_alpha = dir.path() / "background_frontal.png";
  ASSERT_TRUE(cv::imwrite(with_alpha.string(), cv::Mat(kH, kW, CV_8UC4, cv::Scalar(90, 90, 90, 10))));
  auto r = load_background_images(with_alpha, with_alpha, kW, kH);
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_TRUE(r->frontal.colour());
  for (std::size_t i = 0; i < r->frontal.pixels.size(); i += 2) ASSERT_NEAR(r->frontal.pixels[i], 90, 1) << i;
}

// A file cut short (a copy interrupted): its header is whole, its pixels
// are not. One message naming the file, no partial scene.
TEST(BackgroundImages, ACutFileIsAnErrorNamingIt) {
  test::TempDir dir;
  SceneImage grey{kW, kH, 1, std::vector<std::uint8_t>(kW * kH)};
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) grey.pixels[i] = static_cast<std::uint8_t>(i * 7 % 251);
  ASSERT_TRUE(write_background_images(dir.path(), {grey, grey}));
  const auto cut = dir.path() / kBackgroundFiles[0];
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) / 2);
  auto r = load_background_images(dir.path(), kW, kH);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message.rfind(cut.string() + ": cannot be decoded, cut short or damaged (libpng: ", 0), 0u)
      << r.error().message;
}

// Where the file cannot be made (a directory of that name is in the way):
// one message naming the file and why, nothing written.
TEST(BackgroundImages, AFileThatCannotBeWrittenIsAnErrorNamingIt) {
  test::TempDir dir;
  const auto blocked = dir.path() / kBackgroundFiles[0];
  std::filesystem::create_directories(blocked);
  SceneImage grey{kW, kH, 1, std::vector<std::uint8_t>(kW * kH, 77)};
  auto r = write_background_images(dir.path(), {grey, grey});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, blocked.string() + ": cannot be written: Is a directory");
}

TEST(BackgroundImages, OnlyPngIsRead) {
  test::TempDir dir;
  const auto bmp = dir.path() / "background_frontal.bmp";
  ASSERT_TRUE(cv::imwrite(bmp.string(), cv::Mat(kH, kW, CV_8U, cv::Scalar(90))));
  auto r = load_background_images(bmp, bmp);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, bmp.string() + ": not a PNG file");
}

}  // namespace
}  // namespace spinewatch
