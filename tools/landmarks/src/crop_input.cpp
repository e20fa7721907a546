#include "spinewatch/landmarks/crop_input.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace spinewatch::landmarks {

std::vector<float> crop_to_input(const cv::Mat& bgr, const SquareCrop& crop, int input_side, InputRange range) {
  cv::Mat square(crop.side, crop.side, bgr.type(), cv::Scalar::all(0));
  const cv::Rect wanted(crop.x, crop.y, crop.side, crop.side);
  const cv::Rect inside = wanted & cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (!inside.empty()) bgr(inside).copyTo(square(inside - wanted.tl()));
  cv::Mat resized, rgb, unit;
  cv::resize(square, resized, cv::Size(input_side, input_side), 0, 0, cv::INTER_AREA);
  cv::cvtColor(resized, rgb, cv::COLOR_BGR2RGB);
  if (range == InputRange::kUnit) {
    rgb.convertTo(unit, CV_32FC3, 1.0 / 255.0);
  } else {
    rgb.convertTo(unit, CV_32FC3, 2.0 / 255.0, -1.0);
  }
  return std::vector<float>(unit.ptr<float>(), unit.ptr<float>() + static_cast<std::size_t>(input_side) * input_side * 3);
}

cv::Mat mask_to_frame(const std::vector<float>& logits, int input_side, const SquareCrop& crop, cv::Size frame,
                      float threshold) {
  // Threshold on the logit: p > t ⇔ logit > log(t / (1 − t)).
  const float logit_threshold = std::log(threshold / (1.0f - threshold));
  cv::Mat small(input_side, input_side, CV_32F, const_cast<float*>(logits.data()));
  cv::Mat square;
  cv::resize(small, square, cv::Size(crop.side, crop.side), 0, 0, cv::INTER_LINEAR);
  cv::Mat binary = square > logit_threshold;
  cv::Mat out(frame, CV_8U, cv::Scalar(0));
  const cv::Rect wanted(crop.x, crop.y, crop.side, crop.side);
  const cv::Rect inside = wanted & cv::Rect(0, 0, frame.width, frame.height);
  if (!inside.empty()) binary(inside - wanted.tl()).copyTo(out(inside));
  return out;
}

}  // namespace spinewatch::landmarks
