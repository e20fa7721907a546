#pragma once
// The live view's pictures as JPEG, through libjpeg-turbo's TurboJPEG API:
// one compressor kept for the render thread's lifetime instead of one set
// up per picture, and no OpenCV imgcodecs (with its ~140 shared libraries)
// in the daemon.
#include <memory>
#include <string>

#include <opencv2/core/mat.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch {

class JpegEncoder {
 public:
  JpegEncoder();
  // `image`: 8-bit B, G, R (chroma subsampled 4:2:0) or grey; `quality`
  // 1..100 as libjpeg's. Not thread-safe: one encoder per thread.
  Result<std::string> encode(const cv::Mat& image, int quality);

 private:
  struct Destroy {
    void operator()(void* handle) const;
  };
  std::unique_ptr<void, Destroy> handle_;
};

}  // namespace spinewatch
