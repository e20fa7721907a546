#include "spinewatch/import/crop.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace spinewatch::import {

std::string CropRect::describe() const {
  return fmt::format("{}x{}+{}+{} (scale {:.4g})", width, height, x, y, scale());
}

Status check_crop(const CropRect& c, int frame_width, int frame_height) {
  if (c.width <= 0 || c.height <= 0 || c.width % 4 != 0 || c.height * 4 != c.width * 3)
    return Error{fmt::format("crop {}x{}: must be 4:3 ({}x{} scaled uniformly) with a width that is a multiple of "
                             "4, e.g. 640,480 or 960,720",
                             c.width, c.height, kOutWidth, kOutHeight)};
  if (c.x < 0 || c.y < 0 || c.x + c.width > frame_width || c.y + c.height > frame_height)
    return Error{fmt::format("crop {}x{}+{}+{}: not inside the {}x{} frame", c.width, c.height, c.x, c.y,
                             frame_width, frame_height)};
  return Ok{};
}

Result<CropRect> parse_crop(std::string_view text, int frame_width, int frame_height) {
  std::vector<int> v;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    int n = 0;
    const auto [end, ec] = std::from_chars(text.data() + at, text.data() + comma, n);
    if (ec != std::errc{} || end != text.data() + comma)
      return Error{fmt::format("--crop \"{}\": expected X,Y,W,H in pixels of the video", text)};
    v.push_back(n);
    at = comma + 1;
  }
  if (v.size() != 4) return Error{fmt::format("--crop \"{}\": expected X,Y,W,H (four numbers)", text)};
  CropRect c{v[0], v[1], v[2], v[3]};
  if (auto s = check_crop(c, frame_width, frame_height); !s) return Error{"--crop: " + s.error().message};
  return c;
}

CropRect crop_around(int box_x, int box_y, int box_w, int box_h, int frame_width, int frame_height, double margin,
                     int min_width) {
  // The largest 4:3 rectangle the frame holds, widths in steps of 4.
  const int max_width = std::min(frame_width, frame_height * 4 / 3) / 4 * 4;
  const double want_w = std::max({box_w * (1 + 2 * margin), box_h * (1 + 2 * margin) * 4.0 / 3.0,
                                  static_cast<double>(min_width)});
  const int width = std::min(max_width, static_cast<int>(std::ceil(want_w / 4.0)) * 4);
  const int height = width * 3 / 4;
  const double cx = box_x + box_w / 2.0, cy = box_y + box_h / 2.0;
  const int x = std::clamp(static_cast<int>(std::lround(cx - width / 2.0)), 0, frame_width - width);
  const int y = std::clamp(static_cast<int>(std::lround(cy - height / 2.0)), 0, frame_height - height);
  return CropRect{x, y, width, height};
}

CameraModel crop_camera(const CameraModel& camera, const CropRect& c) {
  CameraModel out = camera;
  const double s = c.scale();
  Eigen::Matrix3d& K = out.camera_matrix;
  K(0, 0) *= s;
  K(0, 1) *= s;
  K(1, 1) *= s;
  K(0, 2) = crop_x(camera.camera_matrix(0, 2), c);
  K(1, 2) = crop_y(camera.camera_matrix(1, 2), c);
  out.image_width = kOutWidth;
  out.image_height = kOutHeight;
  return out;
}

}  // namespace spinewatch::import
