#include "silhouette/person_prior.hpp"

#include <vector>

#include <opencv2/imgproc.hpp>

namespace spinewatch {

BitMask person_prior(const CameraModel& camera, int width, int height, const PersonBox& box) {
  std::vector<cv::Point2f> corners;
  for (double x : {box.x_min_mm, box.x_max_mm})
    for (double y : {0.0, box.y_max_mm})
      for (double z : {-box.z_half_mm, box.z_half_mm}) {
        const auto pixel = camera.project({x, y, z});
        if (!pixel) return BitMask(width, height);  // behind the camera: no prior
        corners.emplace_back(static_cast<float>(pixel->x()), static_cast<float>(pixel->y()));
      }
  std::vector<cv::Point2f> hull;
  cv::convexHull(corners, hull);
  std::vector<cv::Point> polygon;
  for (const auto& p : hull) polygon.emplace_back(cvRound(p.x), cvRound(p.y));
  cv::Mat image(height, width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(image, polygon, 255);
  BitMask out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (image.at<std::uint8_t>(y, x)) out.set(x, y);
  return out;
}

}  // namespace spinewatch
