#pragma once
// Video compression of the phantom's frames (docs/phantom.md, "Video
// compression"): each view's frames through an H.264 encoder (libx264, as
// a webcam or an IP camera compresses, 4:2:0) and its decoder, in order, so
// the blocks, the smoothing and the frame-to-frame residue are H.264's own.
#include <memory>

#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"

namespace spinewatch::phantom {

// x264's constant-rate factor: 0 lossless, 23 its default, 51 the worst.
inline constexpr int kMinCrf = 0, kMaxCrf = 51;

struct CodedFrame {
  cv::Mat luma;    // CV_8U
  cv::Mat chroma;  // CV_8UC2 (U, V) per pixel; empty when none was given
};

class H264RoundTrip {
 public:
  // One stream of `size` frames at 30 fps; an error when this machine's
  // libavcodec has no libx264 encoder or H.264 decoder.
  static Result<H264RoundTrip> create(cv::Size size, int crf);
  H264RoundTrip(H264RoundTrip&&) noexcept;
  H264RoundTrip& operator=(H264RoundTrip&&) noexcept;
  ~H264RoundTrip();

  // The next frame, encoded and decoded at once (no B-frames, no look-ahead:
  // one frame out for each frame in). `chroma` (CV_8UC2) may be empty: grey.
  Result<CodedFrame> pass(const cv::Mat& luma, const cv::Mat& chroma);

 private:
  struct Codec;
  explicit H264RoundTrip(std::unique_ptr<Codec> codec);
  std::unique_ptr<Codec> codec_;
};

}  // namespace spinewatch::phantom
