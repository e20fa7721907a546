#include "spinewatch/calibrate/grey_image.hpp"

namespace spinewatch {

cv::Mat grey_image(const Frame& frame) {
  const LumaView luma = frame.luma();
  cv::Mat grey(luma.height, luma.width, CV_8U);
  for (int y = 0; y < luma.height; ++y)
    for (int x = 0; x < luma.width; ++x) grey.at<std::uint8_t>(y, x) = luma.at(x, y);
  return grey;
}

}  // namespace spinewatch
