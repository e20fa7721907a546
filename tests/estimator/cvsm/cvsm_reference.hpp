#pragma once
// The float reference for the CVSM cost, with OpenCV: control points
// projected with CameraModel::project (double), each segment's convex hull
// (cv::convexHull) filled with cv::fillPoly, then cv::bitwise_xor and
// cv::countNonZero against the silhouette. Used by the tests (agreement)
// and bench/cvsm (speed-up).
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"
#include "bit_mask_mat.hpp"

namespace spinewatch::test {

inline void render_reference(const CameraModel& cam, const BodyModel& model,
                             const std::vector<Eigen::Vector3d>& points, cv::Mat& out) {
  out.setTo(0);
  std::vector<cv::Point2f> proj(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto p = cam.project(points[i]);
    proj[i] = p ? cv::Point2f(static_cast<float>(p->x()), static_cast<float>(p->y())) : cv::Point2f(-1e4f, -1e4f);
  }
  std::vector<cv::Point2f> seg(2 * kControlPoints), hull;
  std::vector<std::vector<cv::Point>> poly(1);
  for (const auto& chain : model.chains)
    for (std::size_t s = 0; s + 1 < chain.size(); ++s) {
      for (int k = 0; k < kControlPoints; ++k) {
        seg[static_cast<std::size_t>(k)] = proj[static_cast<std::size_t>(chain[s] * kControlPoints + k)];
        seg[static_cast<std::size_t>(kControlPoints + k)] = proj[static_cast<std::size_t>(chain[s + 1] * kControlPoints + k)];
      }
      cv::convexHull(seg, hull);
      poly[0].clear();
      for (const auto& p : hull) poly[0].emplace_back(cvRound(p.x * 256), cvRound(p.y * 256));
      cv::fillPoly(out, poly, cv::Scalar(255), cv::LINE_8, 8);
    }
}

// XOR pixel count of the model against a silhouette (both CV_8U 0/255).
inline std::int64_t reference_xor(const CameraModel& cam, const BodyModel& model,
                                  const std::vector<Eigen::Vector3d>& points, const cv::Mat& silhouette,
                                  cv::Mat& scratch, cv::Mat& diff) {
  scratch.create(silhouette.size(), CV_8U);
  render_reference(cam, model, points, scratch);
  cv::bitwise_xor(scratch, silhouette, diff);
  return cv::countNonZero(diff);
}

}  // namespace spinewatch::test
