#include "spinewatch/estimator/calibration/station_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "camera_views.hpp"

namespace spinewatch {
namespace {

using namespace calibration_detail;

constexpr const char* kNames[2] = {"frontal", "lateral"};

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

// The board's pose in one camera from every placement frame at once (the
// board lies still, so more frames only average the noise).
struct BoardPose {
  Eigen::Matrix3d R;  // board → camera: x_cam = R · X_board + t
  Eigen::Vector3d t;
};

Result<BoardPose> locate_board(const CalibrationBoard& board, const CameraModel& camera,
                               const std::vector<cv::Mat>& frames, const CalibrationLimits& limits,
                               CameraReport& report) {
  std::vector<int> ids;
  std::vector<cv::Point2f> pixels;
  std::set<int> distinct;
  report.placement_frames = static_cast<int>(frames.size());
  int most_markers = 0;
  for (const auto& frame : frames) {
    BoardDetection found = board.detect(frame);
    most_markers = std::max(most_markers, found.markers);
    if (!board.usable(found, limits.min_corners)) continue;
    ++report.placement_frames_with_board;
    ids.insert(ids.end(), found.ids.begin(), found.ids.end());
    pixels.insert(pixels.end(), found.pixels.begin(), found.pixels.end());
    distinct.insert(found.ids.begin(), found.ids.end());
  }
  report.placement_corners = static_cast<int>(distinct.size());
  if (ids.empty())
    return Error{fmt::format(
        "{} camera: the placement board was not found (with at least {} corners) in any of the {} placement frames "
        "({}): place the board where the subject will stand so that both cameras see it whole — upright with its "
        "face turned halfway between the cameras, or flat on the floor — and record the placement again",
        report.name, limits.min_corners, frames.size(),
        board.spec().kind == BoardKind::Charuco ? fmt::format("at most {} markers in a frame", most_markers)
                                                : std::string("no complete chessboard in any frame"))};
  const cv::Mat K = camera_matrix_cv(camera), dist = dist_coeffs_cv(camera);
  const std::vector<cv::Point3f> object = board.object_points(ids);
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    // IPPE gives both poses a planar target allows; the better one, refined.
    cv::solvePnPGeneric(object, pixels, K, dist, rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
    if (rvecs.empty()) return Error{fmt::format("{} camera: cv::solvePnP found no pose of the placement board", report.name)};
    for (std::size_t k = 1; k < rvecs.size(); ++k)
      if (reprojection_rms(board, camera, ids, pixels, rvecs[k], tvecs[k]) <
          reprojection_rms(board, camera, ids, pixels, rvecs[0], tvecs[0])) {
        std::swap(rvecs[0], rvecs[k]);
        std::swap(tvecs[0], tvecs[k]);
      }
    cv::solvePnPRefineLM(object, pixels, K, dist, rvecs[0], tvecs[0]);
  } catch (const cv::Exception& e) {
    return Error{fmt::format("{} camera: cv::solvePnP failed on the placement board ({})", report.name, e.err)};
  }
  report.placement_rms_px = reprojection_rms(board, camera, ids, pixels, rvecs[0], tvecs[0]);
  BoardPose pose;
  cv::Mat R;
  cv::Rodrigues(rvecs[0], R);
  cv::cv2eigen(R, pose.R);
  cv::cv2eigen(tvecs[0], pose.t);
  return pose;
}

// The world frame of docs/interfaces.md §1 in board coordinates: the board
// gives up (its normal on the floor, its upward edge upright) and the
// origin; X is the horizontal direction from the origin towards the
// frontal camera, Z = X × Y (the subject's right).
struct WorldInBoard {
  Eigen::Matrix3d axes;  // columns: X, Y, Z in board coordinates
  Eigen::Vector3d origin;
};

WorldInBoard world_frame(const CalibrationBoard& board, const BoardPose& frontal, const PlacementSpec& placement) {
  const Eigen::Vector3d camera = -frontal.R.transpose() * frontal.t;  // frontal camera centre, board coordinates
  const Eigen::Vector3d centre = board.centre();
  Eigen::Vector3d up;
  if (placement.kind == Placement::Floor) {
    up = Eigen::Vector3d::UnitZ() * (camera.z() > 0 ? 1.0 : -1.0);  // the cameras are above the floor
  } else {
    // The board's edge nearest to the frontal camera's image-up direction.
    const Eigen::Vector3d image_up = -frontal.R.transpose().col(1);
    const Eigen::Vector3d candidates[4] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(),
                                           Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitY()};
    up = *std::max_element(std::begin(candidates), std::end(candidates),
                           [&](const auto& a, const auto& b) { return a.dot(image_up) < b.dot(image_up); });
  }
  WorldInBoard w;
  w.origin = placement.kind == Placement::Floor ? centre : Eigen::Vector3d(centre - placement.centre_height_mm * up);
  Eigen::Vector3d towards = camera - w.origin;
  towards -= towards.dot(up) * up;
  const Eigen::Vector3d x = towards.normalized();
  w.axes.col(0) = x;
  w.axes.col(1) = up;
  w.axes.col(2) = x.cross(up);
  return w;
}

CameraModel place(const CameraModel& intrinsics, const BoardPose& pose, const WorldInBoard& world) {
  CameraModel cam = intrinsics;
  cam.R = pose.R * world.axes;
  cam.t = pose.R * world.origin + pose.t;
  return cam;
}

// A chessboard's corners are numbered from whichever end the detector
// starts: the lateral camera's numbering may be the frontal's turned by
// 180° about the board's centre. The lateral camera stands on the
// subject's right (+Z), which tells the two apart.
BoardPose turned(const CalibrationBoard& board, const BoardPose& pose) {
  const Eigen::Matrix3d half_turn = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  const Eigen::Vector3d c = board.centre();
  return {pose.R * half_turn, pose.t + pose.R * (c - half_turn * c)};
}

std::string worst_views(const CameraReport& r) {
  std::vector<ViewError> v = r.views;
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.rms_px > b.rms_px; });
  std::string s;
  for (std::size_t i = 0; i < std::min<std::size_t>(3, v.size()); ++i)
    s += fmt::format("{}frame {} ({:.2f} px)", i ? ", " : "", v[i].frame, v[i].rms_px);
  return s;
}

// The intrinsics of camera `i`, from elsewhere or from its views; nothing
// (and a problem) when they cannot be had.
std::optional<CameraModel> intrinsics_of(const CalibrationBoard& board, const CameraFrames& frames, cv::Size size,
                                         const CalibrationLimits& limits, CameraReport& r,
                                         std::vector<std::string>& problems) {
  if (frames.intrinsics) {
    r.intrinsics_given = true;
    const CameraModel& given = *frames.intrinsics;
    if (given.image_width > 0 && (given.image_width != size.width || given.image_height != size.height)) {
      problems.push_back(fmt::format("{} camera: the intrinsics given were calibrated at {}x{} (image_width, "
                                     "image_height) but the recordings are {}x{}; calibrate at {}x{}",
                                     r.name, given.image_width, given.image_height, size.width, size.height,
                                     size.width, size.height));
      return std::nullopt;
    }
    return given;
  }
  const auto views = collect_views(board, frames.views, limits, r);
  if (r.frames_with_board == 0) {
    problems.push_back(fmt::format(
        "{} camera: the board was not found in any of the {} frames of the views ({}): hold the board ({}) whole in "
        "the {} camera's view, 1–3 m away and well lit, and check that --board, --squares, --square-mm, "
        "--marker-mm and --dictionary describe the printed board",
        r.name, r.frames,
        board.spec().kind == BoardKind::Charuco ? fmt::format("at most {} of its markers in a frame", r.max_markers)
                                                : std::string("no complete chessboard in any frame"),
        board.describe(), r.name));
    return std::nullopt;
  }
  if (static_cast<int>(views.size()) < limits.min_views) {
    problems.push_back(fmt::format(
        "{} camera: {} distinct views of the board with at least {} corners ({}); at least {} are needed: hold the "
        "board at more poses — near each corner and the centre of the image, tilted 20–45° each way, near and far",
        r.name, views.size(), limits.min_corners, r.seen(), limits.min_views));
    return std::nullopt;
  }
  auto fit = fit_intrinsics(board, views, size);
  if (!fit) {
    problems.push_back(fmt::format("{} camera: {} ({})", r.name, fit.error().message, r.seen()));
    return std::nullopt;
  }
  r.views = fit->views;
  r.rms_px = fit->rms_px;
  if (r.rms_px > limits.max_error_px) {
    problems.push_back(fmt::format(
        "{} camera: reprojection error {:.2f} px RMS over {} views, more than {:.2f} px; worst views: {}: a blurred "
        "frame, a board that is not flat or moved during the exposure; record those poses again holding the board "
        "still (or allow more with --max-error)",
        r.name, r.rms_px, r.views.size(), limits.max_error_px, worst_views(r)));
    return std::nullopt;
  }
  return fit->camera;
}

std::string vec(const Eigen::Vector3d& v) { return fmt::format("({:.0f}, {:.0f}, {:.0f})", v.x(), v.y(), v.z()); }

}  // namespace

std::string CameraReport::seen() const {
  if (intrinsics_given) return "intrinsics given";
  return fmt::format("board in {} of {} frames, {} with enough corners, {} distinct views, {:.0f} corners on average",
                     frames_with_board, frames, frames_usable, distinct_views, mean_corners);
}

StationCalibration calibrate_station(const CalibrationBoard& board, const std::array<CameraFrames, 2>& frames,
                                     cv::Size image_size, const PlacementSpec& placement,
                                     const CalibrationLimits& limits) {
  StationCalibration out;
  CalibrationReport& report = out.report;
  report.board = board.describe();
  std::array<std::optional<CameraModel>, 2> intrinsics;
  for (int i = 0; i < 2; ++i) {
    report.cameras[i].name = kNames[i];
    intrinsics[i] = intrinsics_of(board, frames[i], image_size, limits, report.cameras[i], report.problems);
  }

  std::array<std::optional<BoardPose>, 2> poses;
  for (int i = 0; i < 2; ++i) {
    if (!intrinsics[i]) continue;
    auto pose = locate_board(board, *intrinsics[i], frames[i].placement, limits, report.cameras[i]);
    if (!pose) {
      report.problems.push_back(pose.error().message);
      continue;
    }
    if (report.cameras[i].placement_rms_px > limits.max_error_px)
      report.problems.push_back(fmt::format(
          "{} camera: the placement board reprojects with {:.2f} px RMS, more than {:.2f} px: the board moved during "
          "the placement recording, or is not flat; record the placement again with the board still",
          kNames[i], report.cameras[i].placement_rms_px, limits.max_error_px));
    poses[i] = *pose;
  }
  if (!poses[0] || !poses[1]) return out;

  const WorldInBoard world = world_frame(board, *poses[0], placement);
  CameraRig& rig = out.rig;
  rig.frontal = place(*intrinsics[0], *poses[0], world);
  rig.lateral = place(*intrinsics[1], *poses[1], world);
  if (board.spec().kind == BoardKind::Chessboard && rig.lateral.centre_in_world().z() < 0)
    rig.lateral = place(*intrinsics[1], turned(board, *poses[1]), world);
  for (CameraModel* cam : {&rig.frontal, &rig.lateral}) {
    cam->image_width = image_size.width;
    cam->image_height = image_size.height;
  }
  report.placed = true;
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  for (int i = 0; i < 2; ++i) {
    report.cameras[i].centre = cams[i]->centre_in_world();
    report.cameras[i].axis = cams[i]->R.transpose() * Eigen::Vector3d::UnitZ();
  }
  report.axis_angle_deg =
      degrees(std::acos(std::clamp(report.cameras[0].axis.dot(report.cameras[1].axis), -1.0, 1.0)));
  const Eigen::Vector3d flat[2] = {report.cameras[0].axis.cwiseProduct(Eigen::Vector3d(1, 0, 1)),
                                   report.cameras[1].axis.cwiseProduct(Eigen::Vector3d(1, 0, 1))};
  report.horizontal_axis_angle_deg =
      flat[0].norm() < 1e-6 || flat[1].norm() < 1e-6
          ? 0.0
          : degrees(std::acos(std::clamp(flat[0].normalized().dot(flat[1].normalized()), -1.0, 1.0)));
  if (std::abs(report.horizontal_axis_angle_deg - 90) > limits.axis_tolerance_deg)
    report.problems.push_back(fmt::format(
        "the cameras' optical axes are {:.1f}° apart seen from above; the station needs them 90° ± {:.0f}° apart "
        "(frontal camera at {} mm, lateral at {} mm): turn the lateral camera so that it looks at the subject's "
        "side, square to the frontal camera, and calibrate again",
        report.horizontal_axis_angle_deg, limits.axis_tolerance_deg, vec(report.cameras[0].centre),
        vec(report.cameras[1].centre)));
  for (int i = 0; i < 2; ++i)
    if (report.cameras[i].centre.y() <= 0)
      report.problems.push_back(fmt::format(
          "{} camera: {:.0f} mm below the floor: the board's placement is not what was given (--placement{})",
          kNames[i], -report.cameras[i].centre.y(),
          placement.kind == Placement::Upright ? ", --board-centre-height" : ""));
  if (report.cameras[1].centre.z() < 0)
    report.warnings.push_back(fmt::format(
        "the lateral camera is on the subject's left (z = {:.0f} mm); docs/interfaces.md §1 puts it on the right",
        report.cameras[1].centre.z()));
  return out;
}

std::string format_report(const CalibrationReport& report) {
  std::string s = fmt::format("board: {}\n", report.board);
  for (const CameraReport& c : report.cameras) {
    s += fmt::format("{}: {}\n", c.name, c.seen());
    if (!c.intrinsics_given && !c.views.empty()) {
      s += fmt::format("  intrinsics: {:.3f} px RMS over {} views\n", c.rms_px, c.views.size());
      for (const ViewError& v : c.views)
        s += fmt::format("    view frame {:>4}: {:>3} corners, {:.3f} px{}\n", v.frame, v.corners, v.rms_px,
                         v.left_out ? " (left out: far worse than the others)" : "");
    }
    if (c.placement_frames > 0)
      s += fmt::format("  placement: board in {} of {} frames, {} corners, {:.3f} px RMS\n",
                       c.placement_frames_with_board, c.placement_frames, c.placement_corners, c.placement_rms_px);
    if (report.placed)
      s += fmt::format("  position: {} mm, optical axis ({:.3f}, {:.3f}, {:.3f})\n", vec(c.centre), c.axis.x(),
                       c.axis.y(), c.axis.z());
  }
  if (report.placed)
    s += fmt::format("angle between the optical axes: {:.2f}° ({:.2f}° seen from above)\n", report.axis_angle_deg,
                     report.horizontal_axis_angle_deg);
  for (const auto& w : report.warnings) s += fmt::format("warning: {}\n", w);
  for (const auto& p : report.problems) s += fmt::format("refused: {}\n", p);
  return s;
}

}  // namespace spinewatch
