#pragma once
// A BitMask as an 8-bit OpenCV image (0 / 255) and back, for tests and
// benchmarks that compare the bit-packed code with OpenCV's.
#include <cstdint>

#include <opencv2/core.hpp>

#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::test {

inline cv::Mat to_mat(const BitMask& m) {
  cv::Mat out(m.height(), m.width(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x)
      if (m.get(x, y)) out.at<std::uint8_t>(y, x) = 255;
  return out;
}

// Every non-zero pixel is set.
inline BitMask to_mask(const cv::Mat& m) {
  BitMask out(m.cols, m.rows);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      if (m.at<std::uint8_t>(y, x)) out.set(x, y);
  return out;
}

}  // namespace spinewatch::test
