#pragma once
// PNG files through libpng, not OpenCV's imgcodecs: the station reads and
// writes no other image format, and imgcodecs brings its other codecs
// along (GDAL, GDCM, OpenEXR, HEIF: about 140 shared libraries loaded at
// every start of the daemon). Read with the simplified API (png_image),
// written with the full one (write_png says why).
#include <cstdint>
#include <filesystem>
#include <memory>

#include <opencv2/core/mat.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

// A PNG file whose header has been read: its size is known before any
// pixel is decoded or allocated.
class PngFile {
 public:
  // Fails with "<path>: not a PNG file" on anything without the PNG
  // signature, else with libpng's reason for a header it cannot read.
  static Result<PngFile> open(const std::filesystem::path& path);

  PngFile(PngFile&&) noexcept;
  PngFile& operator=(PngFile&&) noexcept;
  ~PngFile();

  std::uint32_t width() const;
  std::uint32_t height() const;
  bool colour() const;
  // 16 bits a sample: libpng would convert it from linear light to 8-bit
  // sRGB on the way in, which is not what a camera's levels are.
  bool deep() const;

  // The pixels as 8-bit grey (CV_8UC1) or B, G, R (CV_8UC3); an alpha
  // channel is dropped, as it is in the station's frames. Once only.
  Result<cv::Mat> decode();

 private:
  struct Header;
  explicit PngFile(std::unique_ptr<Header> header, std::filesystem::path path);
  std::unique_ptr<Header> header_;
  std::filesystem::path path_;
};

// Writes an 8-bit grey or B, G, R image as a PNG file; errors name the
// file and why ("cannot be written: <errno's text or libpng's>").
Status write_png(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace spinewatch
