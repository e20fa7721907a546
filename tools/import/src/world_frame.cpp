#include "spinewatch/import/world_frame.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <numbers>
#include <sstream>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace spinewatch::import {
namespace {

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

std::string vec(const Eigen::Vector3d& v, int decimals = 3) {
  return fmt::format("({:.{}f}, {:.{}f}, {:.{}f})", v.x(), decimals, v.y(), decimals, v.z(), decimals);
}

// The world directions an upright view of the camera's image calls "up"
// and "right": R's rows are the camera's axes in the world, image y points
// down; a caliscope rotation_count of 1 turns the image 90° clockwise for
// display (its top is then the camera's −x, its right the camera's −y),
// −1 or 3 counter-clockwise, 2 half a turn.
struct UprightAxes {
  Eigen::Vector3d up, right;
};
UprightAxes upright_axes(const NamedCamera& cam) {
  const Eigen::Vector3d x = cam.model.R.row(0).transpose(), y = cam.model.R.row(1).transpose();
  switch (((cam.rotation_count % 4) + 4) % 4) {
    case 1: return {-x, -y};
    case 2: return {y, -x};
    case 3: return {x, y};
    default: return {-y, x};
  }
}

// Where the two optical axes pass closest (the midpoint), the point both
// cameras look at; nothing when the axes are near parallel.
std::optional<Eigen::Vector3d> look_at_point(const CameraModel& a, const CameraModel& b) {
  const Eigen::Vector3d ca = a.centre_in_world(), cb = b.centre_in_world();
  const Eigen::Vector3d da = a.R.row(2).transpose(), db = b.R.row(2).transpose();
  const Eigen::Vector3d w = ca - cb;
  const double c = da.dot(db), d = da.dot(w), e = db.dot(w), den = 1 - c * c;
  if (den < 1e-6) return std::nullopt;
  const double sa = (c * e - d) / den, sb = (e - c * d) / den;
  if (sa <= 0 || sb <= 0) return std::nullopt;  // behind a camera
  return 0.5 * ((ca + sa * da) + (cb + sb * db));
}

}  // namespace

CameraModel WorldFrame::to_station(const CameraModel& camera) const {
  CameraModel out = camera;
  out.R = camera.R * axes.transpose();
  out.t = camera.R * origin + camera.t;
  return out;
}

Result<Eigen::Vector3d> parse_up(const std::string& text) {
  std::istringstream in(text);
  Eigen::Vector3d v;
  char c1 = 0, c2 = 0;
  if (!(in >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !(in >> std::ws).eof() ||
      !v.allFinite() || v.norm() < 1e-9)
    return Error{fmt::format("--up \"{}\": expected X,Y,Z, a non-zero direction in the calibration's frame "
                             "(e.g. 0,0,1 for caliscope's board-on-the-floor origin)",
                             text)};
  return v.normalized();
}

Result<Eigen::Vector3d> estimate_up(const CameraArray& array, std::vector<std::string>& report) {
  // A camera held level (not rolled) has a horizontal image "right"
  // whatever its pitch: up is the direction most nearly perpendicular to
  // every camera's right (least squares: the smallest eigenvector of
  // Σ right·rightᵀ), turned to agree with their image "up"s. Their mean
  // alone would lean towards where cameras looking down look.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean_up = Eigen::Vector3d::Zero();
  std::vector<const NamedCamera*> used;
  for (const NamedCamera& cam : array.cameras)
    if (!cam.ignored && cam.has_extrinsics) {
      const UprightAxes axes = upright_axes(cam);
      scatter += axes.right * axes.right.transpose();
      mean_up += axes.up;
      used.push_back(&cam);
    }
  if (used.empty() || mean_up.norm() < 0.3 * static_cast<double>(used.size()))
    return Error{fmt::format("{}: the cameras' image \"up\" directions disagree (or there are none): give the up "
                             "axis with --up X,Y,Z in the calibration's frame",
                             array.source)};
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);  // eigenvalues ascending
  Eigen::Vector3d up;
  std::string how;
  // Two rights at least 15° apart pin it (the second eigenvalue then
  // exceeds sin²15° / 2 ≈ 0.033); else the image "up"s' mean.
  if (used.size() >= 2 && solver.eigenvalues()(1) > 0.033) {
    up = solver.eigenvectors().col(0);
    if (up.dot(mean_up) < 0) up = -up;
    how = fmt::format("perpendicular to the image horizontals of {} cameras (least squares)", used.size());
  } else {
    up = mean_up.normalized();
    how = fmt::format("the mean image \"up\" of {} camera{} (their horizontals do not pin it)", used.size(),
                      used.size() == 1 ? "" : "s");
  }
  std::string roll;
  for (const NamedCamera* cam : used)
    roll += fmt::format("{}{} {:.0f}°", roll.empty() ? "" : ", ", cam->id,
                        std::asin(std::clamp(upright_axes(*cam).right.dot(up), -1.0, 1.0)) * 180.0 / std::numbers::pi);
  report.push_back(fmt::format("up {} in the calibration's frame: {}; the cameras' roll against it: {}; give "
                               "--up X,Y,Z when the calibration knows the floor",
                               vec(up), how, roll));
  return up;
}

Result<WorldFrame> choose_world_frame(const CameraRig& rig, const Eigen::Vector3d& up, double camera_height_mm) {
  WorldFrame frame;
  const Eigen::Vector3d cf = rig.frontal.centre_in_world(), cl = rig.lateral.centre_in_world();
  auto target = look_at_point(rig.frontal, rig.lateral);
  Eigen::Vector3d p;
  if (target) {
    p = *target;
    frame.report.push_back(fmt::format("look-at point {} mm: where the two optical axes pass closest", vec(p, 0)));
  } else {
    p = cf + 1500.0 * rig.frontal.R.row(2).transpose();
    frame.report.push_back(fmt::format("look-at point {} mm: the axes do not meet in front of both cameras; 1.5 m "
                                       "in front of the frontal camera",
                                       vec(p, 0)));
  }
  const Eigen::Vector3d to_frontal = cf - p;
  const Eigen::Vector3d horizontal = to_frontal - to_frontal.dot(up) * up;
  if (horizontal.norm() < 0.05 * to_frontal.norm())
    return Error{"the frontal camera looks straight down or up at the subject: no horizontal direction towards it "
                 "(X of interfaces.md §1); choose another camera pair or another --up"};
  const Eigen::Vector3d x = horizontal.normalized();
  const Eigen::Vector3d z = x.cross(up);
  frame.axes.row(0) = x.transpose();
  frame.axes.row(1) = up.transpose();
  frame.axes.row(2) = z.transpose();
  const double cameras_height = (0.5 * (cf + cl) - p).dot(up);
  frame.origin = p + (cameras_height - camera_height_mm) * up;
  frame.report.push_back(fmt::format("X {} towards the frontal camera (horizontal), Y {} up, Z = X × Y {}",
                                     vec(x), vec(up), vec(z)));
  frame.report.push_back(fmt::format("origin {} mm: on the floor below the look-at point, taken {:.0f} mm below the "
                                     "cameras' mean height (--camera-height)",
                                     vec(frame.origin, 0), camera_height_mm));
  const Eigen::Vector3d lateral_at = frame.to_station(cl);
  const Eigen::Vector3d frontal_at = frame.to_station(cf);
  frame.report.push_back(fmt::format("frontal camera at {} mm, lateral at {} mm; {:.0f}° between their axes",
                                     vec(frontal_at, 0), vec(lateral_at, 0),
                                     degrees_between(rig.frontal.R.row(2).transpose(), rig.lateral.R.row(2).transpose())));
  if (lateral_at.z() < 0)
    frame.report.push_back("warning: the lateral camera is on the subject's left (Z < 0); interfaces.md §1 puts it "
                           "on the right — swap --cameras if the subject faces the frontal camera");
  return frame;
}

}  // namespace spinewatch::import
