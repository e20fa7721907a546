#pragma once
// Integer projection of control points (the CVSM fast path).
//
// Format: world points are int32 in Q4 (1/16 mm); the camera rotation is
// int64 in Q20 and the translation Q24 (mm · 2^24), so camera coordinates
// are exact int64 in Q24; pixels come out as int32 in Q8 (1/256 px), with
// the pixel centre of column c at c·256 (OpenCV's convention).
//
// Error bound against CameraModel::project for a distortion-free camera and
// a point at depth Z ≥ 1000 mm with |X|,|Y|,|Z| < 4000 mm:
//   rounding the point to Q4:      ≤ √3/32 mm  → ≤ 0.054·f/Z px
//   rounding R to Q20:             ≤ 3·2^-21·4000 mm ≈ 0.006 mm → ≤ 0.006·f/Z px
//   truncating the division to Q8: ≤ 1/256 px
// i.e. below 0.025 px at f = 300 px, Z ≥ 1000 mm — far under the half pixel
// that decides a boundary pixel. Cameras with lens distortion fall back to
// CameraModel::project (double), rounded to Q8.
#include <cstdint>

#include <Eigen/Core>

#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch {

// |Q8| coordinates are clamped to this, ±1024 px: far outside any image (a
// point just in front of a camera, or where a lens's distortion polynomial
// runs away outside its field, projects anywhere), and within the range
// where a ring's packed keys stay exact (segment_scan.hpp). Beyond it a
// key's point index was lost and the scan read past the ring's points
// (a real camera's distortion, caliscope's cam_2, ASan).
inline constexpr std::int32_t kQ8Limit = 1024 * 256;

struct PixelQ8 {
  std::int32_t u = 0, v = 0;
};

class FixedCamera {
 public:
  explicit FixedCamera(const CameraModel& camera);
  // False when the point is behind (or within 1 mm of) the camera plane.
  bool project(const Eigen::Vector3d& world, PixelQ8& out) const;
  bool integer_path() const { return !camera_.has_distortion(); }

 private:
  CameraModel camera_;
  std::int64_t r_[3][3];   // Q20
  std::int64_t t_[3];      // Q24
  std::int64_t fx_, fy_, cx_, cy_;  // Q8
  bool distorted_ = false;
};

}  // namespace spinewatch
