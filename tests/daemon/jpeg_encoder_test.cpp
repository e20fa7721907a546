// The live view's JPEG encoder (libjpeg-turbo's TurboJPEG API), checked by
// an independent decoder, OpenCV's imgcodecs, against the reference it
// replaced in the live view (cv::imencode, libjpeg's own API): the picture
// comes back as close as the reference's at the same quality, colour and
// grey, rows with padding included, and what cannot be encoded is an
// error, not a picture.
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "http/jpeg_encoder.hpp"

namespace spinewatch {
namespace {

// Smooth gradients with a few edges, as the live view's overlay draws them.
cv::Mat gradient_scene(int width, int height, int channels) {
  cv::Mat image(height, width, CV_8UC(channels));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c)
        image.ptr<std::uint8_t>(y)[x * channels + c] =
            static_cast<std::uint8_t>((x * (c + 1) + y * (3 - c) + (x / 40 + y / 40) % 2 * 60) % 256);
  return image;
}

cv::Mat jpeg_decoded(const std::string& jpeg, int flags) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(jpeg.size()), CV_8UC1, const_cast<char*>(jpeg.data())), flags);
}

// What cv::imencode's JPEG at `quality` keeps of `image` (PSNR, dB).
double reference_psnr(const cv::Mat& image, int quality) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality}));
  return cv::PSNR(image, cv::imdecode(bytes, cv::IMREAD_UNCHANGED));
}

TEST(JpegEncoder, ColourComesBackAsCloseAsTheReferencesPicture) {
  const cv::Mat image = gradient_scene(320, 240, 3);
  JpegEncoder encoder;
  auto jpeg = encoder.encode(image, 90);
  ASSERT_TRUE(jpeg) << jpeg.error().message;
  const cv::Mat back = jpeg_decoded(*jpeg, cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), image.size());
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_GT(cv::PSNR(image, back), reference_psnr(image, 90) - 0.5);
  EXPECT_GT(cv::PSNR(image, back), 20.0);
  // The channels are not swapped: blue's gradient is blue's.
  cv::Mat swapped;
  cv::cvtColor(image, swapped, cv::COLOR_BGR2RGB);
  EXPECT_GT(cv::PSNR(image, back), cv::PSNR(swapped, back) + 5.0);
}

// The same libjpeg-turbo underneath, the same settings (quality, 4:2:0,
// the accurate DCT, no optimised Huffman tables): the same file.
TEST(JpegEncoder, WritesTheReferencesBytes) {
  for (const int channels : {3, 1}) {
    const cv::Mat image = gradient_scene(320, 240, channels);
    std::vector<std::uint8_t> reference;
    ASSERT_TRUE(cv::imencode(".jpg", image, reference, {cv::IMWRITE_JPEG_QUALITY, 80}));
    JpegEncoder encoder;
    auto jpeg = encoder.encode(image, 80);
    ASSERT_TRUE(jpeg);
    EXPECT_EQ(*jpeg, std::string(reference.begin(), reference.end())) << channels << " channels";
  }
}

TEST(JpegEncoder, GreyStaysOneChannelAndLowerQualityIsSmaller) {
  const cv::Mat image = gradient_scene(160, 120, 1);
  JpegEncoder encoder;
  auto fine = encoder.encode(image, 95);
  auto coarse = encoder.encode(image, 30);
  ASSERT_TRUE(fine && coarse);
  EXPECT_LT(coarse->size(), fine->size());
  const cv::Mat back = jpeg_decoded(*fine, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_8UC1);
  EXPECT_GT(cv::PSNR(image, back), reference_psnr(image, 95) - 0.5);
}

TEST(JpegEncoder, ARegionOfALargerImageIsEncodedByItsRows) {
  const cv::Mat whole = gradient_scene(400, 300, 3);
  const cv::Mat region = whole(cv::Rect(30, 20, 320, 240));  // rows longer than the region's width
  ASSERT_FALSE(region.isContinuous());
  JpegEncoder encoder;
  auto jpeg = encoder.encode(region, 90);
  ASSERT_TRUE(jpeg);
  EXPECT_GT(cv::PSNR(region.clone(), jpeg_decoded(*jpeg, cv::IMREAD_COLOR)), reference_psnr(region.clone(), 90) - 0.5);
}

TEST(JpegEncoder, WhatCannotBeAPictureIsAnError) {
  JpegEncoder encoder;
  EXPECT_FALSE(encoder.encode(cv::Mat(), 80));
  auto deep = encoder.encode(cv::Mat(24, 32, CV_16UC3, cv::Scalar::all(1000)), 80);
  ASSERT_FALSE(deep);
  EXPECT_EQ(deep.error().message, "JPEG: only 8-bit grey or colour images are encoded");
}

}  // namespace
}  // namespace spinewatch
