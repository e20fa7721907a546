#pragma once
// A silhouette turned so that the world's vertical runs down its columns,
// for the measurements that read rows and columns (the subject's centre
// line, the top of the head; subject_estimate.cpp). A camera rolled about
// its optical axis shows the world's verticals leaning by the roll: along
// its rows, the topmost pixel is beside the head and a row's middle is off
// the body's axis. The roll comes from the calibration (docs/cvsm.md,
// "Measuring along the world's vertical"); a camera whose rows are level
// (roll 0, however far it is tilted down) is used as it is.
#include <Eigen/Core>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/estimator/silhouette/bit_mask.hpp"

namespace spinewatch::cvsm_detail {

// The angle (radians) by which the world's up leans in the image from the
// image's up at the principal point, positive towards the image's right:
// the camera's roll about its optical axis. 0 for a camera whose x axis is
// horizontal. Undefined for a camera looking straight up or down (0 then).
double image_roll(const CameraModel& camera);

class UprightView {
 public:
  // Below this roll the mask is used as it is (a thousandth of a degree:
  // far below a pixel across any image).
  static constexpr double kLevelRad = 1e-5;

  UprightView(const CameraModel& camera, const BitMask& mask);

  // The silhouette turned upright about the principal point, on a canvas
  // large enough to hold the whole image; the mask itself when level.
  const BitMask& mask() const { return level_ ? *source_ : turned_; }
  // Whether a pixel of mask() came from the image's border (a person
  // there may continue beyond it). For a level view: the border itself.
  bool on_image_border(int x, int y) const;
  // A point of mask() (pixel coordinates, sub-pixel) in the image.
  Eigen::Vector2d to_image(const Eigen::Vector2d& upright) const;
  double roll() const { return roll_; }
  bool level() const { return level_; }

 private:
  const BitMask* source_;
  bool level_ = true;
  double roll_ = 0;
  Eigen::Vector2d centre_{0, 0};  // principal point, in the image
  Eigen::Vector2d offset_{0, 0};  // where the image's principal point lies on the canvas
  BitMask turned_, border_;
};

}  // namespace spinewatch::cvsm_detail
