#pragma once
// 8-bit BGR (OpenCV's decoded video) to packed YUYV: full-range BT.601
// (OpenCV's YCrCb, JPEG's), the same conversion the station's background
// images go through (capture/background_images.hpp), so a background made
// from the same video matches the frames; Y of each pixel, U and V the
// mean of each horizontal pair.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace spinewatch::import {

// `bgr` CV_8UC3 with an even width; `out` resized to width × height × 2.
void bgr_to_yuyv(const cv::Mat& bgr, std::vector<std::uint8_t>& out);

// The same, one pixel at a time from the BT.601 equations (the tests'
// reference for the fast path).
void bgr_to_yuyv_reference(const cv::Mat& bgr, std::vector<std::uint8_t>& out);

}  // namespace spinewatch::import
