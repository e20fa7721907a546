#include "spinewatch/import/yuyv.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace spinewatch::import {

void bgr_to_yuyv(const cv::Mat& bgr, std::vector<std::uint8_t>& out) {
  cv::Mat ycrcb;
  cv::cvtColor(bgr, ycrcb, cv::COLOR_BGR2YCrCb);
  out.resize(static_cast<std::size_t>(bgr.cols) * static_cast<std::size_t>(bgr.rows) * 2);
  std::uint8_t* o = out.data();
  for (int y = 0; y < ycrcb.rows; ++y) {
    const std::uint8_t* p = ycrcb.ptr<std::uint8_t>(y);
    for (int x = 0; x + 1 < ycrcb.cols; x += 2, p += 6, o += 4) {
      o[0] = p[0];
      o[1] = static_cast<std::uint8_t>((p[2] + p[5] + 1) >> 1);  // U = Cb
      o[2] = p[3];
      o[3] = static_cast<std::uint8_t>((p[1] + p[4] + 1) >> 1);  // V = Cr
    }
  }
}

void bgr_to_yuyv_reference(const cv::Mat& bgr, std::vector<std::uint8_t>& out) {
  out.resize(static_cast<std::size_t>(bgr.cols) * static_cast<std::size_t>(bgr.rows) * 2);
  auto clamp8 = [](double v) { return static_cast<int>(std::clamp(std::lround(v), 0L, 255L)); };
  std::size_t k = 0;
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x + 1 < bgr.cols; x += 2, k += 4) {
      int Y[2], Cb[2], Cr[2];
      for (int i = 0; i < 2; ++i) {
        const cv::Vec3b px = bgr.at<cv::Vec3b>(y, x + i);
        const double b = px[0], g = px[1], r = px[2];
        const double luma = 0.299 * r + 0.587 * g + 0.114 * b;
        Y[i] = clamp8(luma);
        Cb[i] = clamp8((b - luma) * 0.564 + 128);
        Cr[i] = clamp8((r - luma) * 0.713 + 128);
      }
      out[k] = static_cast<std::uint8_t>(Y[0]);
      out[k + 1] = static_cast<std::uint8_t>((Cb[0] + Cb[1] + 1) / 2);
      out[k + 2] = static_cast<std::uint8_t>(Y[1]);
      out[k + 3] = static_cast<std::uint8_t>((Cr[0] + Cr[1] + 1) / 2);
    }
}

}  // namespace spinewatch::import
