#pragma once
// A square crop of a video frame as the landmark model's input, and the
// way back from the crop's pixels to the frame's.
#include <opencv2/core.hpp>
#include <vector>

namespace spinewatch::landmarks {

struct SquareCrop {
  int x = 0, y = 0, side = 0;  // frame pixels; may reach outside the frame (padded black)

  cv::Point2f to_frame(float crop_x, float crop_y, int input_side) const {
    const float scale = static_cast<float>(side) / static_cast<float>(input_side);
    return {static_cast<float>(x) + crop_x * scale, static_cast<float>(y) + crop_y * scale};
  }
};

// The range the 8-bit channels are mapped to. MediaPipe's pose graph feeds
// its landmark model [0, 1]; [-1, 1] is there to check that on real frames
// (docs/cvsm.md, "A learned landmark model beside the fit").
enum class InputRange { kUnit, kSigned };

// BGR frame → input_side² RGB floats in `range`, row-major.
std::vector<float> crop_to_input(const cv::Mat& bgr, const SquareCrop& crop, int input_side,
                                 InputRange range = InputRange::kUnit);

// The model's mask (input_side² logits) back onto the frame: 255 where the
// person's probability exceeds `threshold`, 0 elsewhere and outside the crop.
cv::Mat mask_to_frame(const std::vector<float>& logits, int input_side, const SquareCrop& crop, cv::Size frame,
                      float threshold);

}  // namespace spinewatch::landmarks
