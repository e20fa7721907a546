#pragma once
// A camera frame's luma as the grey image OpenCV's board detector takes.
#include <opencv2/core.hpp>

#include "spinewatch/frames/frame.hpp"

namespace spinewatch {

cv::Mat grey_image(const Frame& frame);  // CV_8U, the frame's size, a copy

}  // namespace spinewatch
