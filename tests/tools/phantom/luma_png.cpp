#include "luma_png.hpp"

#include <opencv2/imgcodecs.hpp>

namespace spinewatch::test {

Status save_luma_png(const LumaView& luma, const std::filesystem::path& path) {
  cv::Mat grey(luma.height, luma.width, CV_8U);
  for (int y = 0; y < luma.height; ++y)
    for (int x = 0; x < luma.width; ++x) grey.at<std::uint8_t>(y, x) = luma.at(x, y);
  if (!cv::imwrite(path.string(), grey)) return Error{path.string() + ": cannot write"};
  return Ok{};
}

}  // namespace spinewatch::test
