#pragma once
// The part of a video frame that becomes the recording's 320×240 image:
// a 4:3 rectangle, scaled uniformly (docs/import.md, "Crop"), and the
// camera model that goes with it.
#include <optional>
#include <string>
#include <string_view>

#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::import {

inline constexpr int kOutWidth = 320, kOutHeight = 240;

struct CropRect {
  int x = 0, y = 0, width = 0, height = 0;
  // Output pixels per source pixel (kOutWidth / width = kOutHeight / height).
  double scale() const { return static_cast<double>(kOutWidth) / width; }
  std::string describe() const;  // "640x480+320+120 (scale 0.5)"
};

// "X,Y,W,H" as given on the command line; W:H must be 4:3 (W a multiple
// of 4) and the rectangle inside the frame.
Result<CropRect> parse_crop(std::string_view text, int frame_width, int frame_height);
Status check_crop(const CropRect& crop, int frame_width, int frame_height);

// The 4:3 rectangle holding `box` (any rectangle of interest, e.g. where
// the clip moved) with a margin, as small as `min_width` allows, no larger
// than the frame, shifted inside it.
CropRect crop_around(int box_x, int box_y, int box_w, int box_h, int frame_width, int frame_height, double margin,
                     int min_width);

// The camera that sees the cropped and scaled image: cv::resize puts an
// output pixel's centre x' over the source position (x' + 0.5) / s − 0.5
// (+ the crop's corner), so x' = (x − x0 + 0.5)·s − 0.5: fx, fy and the
// skew scale by s, the principal point moves by that map, the distortion
// (on normalised coordinates) stays. R and t are unchanged.
CameraModel crop_camera(const CameraModel& camera, const CropRect& crop);

// A pixel of the source image mapped the same way.
inline double crop_x(double x, const CropRect& c) { return (x - c.x + 0.5) * c.scale() - 0.5; }
inline double crop_y(double y, const CropRect& c) { return (y - c.y + 0.5) * c.scale() - 0.5; }

}  // namespace spinewatch::import
