#include "spinewatch/estimator/calibration/station_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "calibration/camera_views.hpp"
#include "calibration/stereo.hpp"

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

// What a board that is not found, or found with a large error, may really
// be: the given one with rows and columns swapped, or the same squares
// with markers of another dictionary. Tried on the views only after a
// refusal; "" when neither fits better.
std::string misdescribed_board(const CalibrationBoard& board, const std::vector<cv::Mat>& frames, cv::Size size,
                               const CalibrationLimits& limits, bool found) {
  const BoardSpec& spec = board.spec();
  if (spec.kind != BoardKind::Charuco) return "";
  auto fits = [&](const BoardSpec& other) {
    auto alternative = CalibrationBoard::create(other);
    if (!alternative) return false;
    CameraReport scratch;
    const auto views = distinct_views(observe_frames(*alternative, frames, limits, scratch), limits, scratch);
    if (static_cast<int>(views.size()) < limits.min_views) return false;
    auto fit = fit_intrinsics(*alternative, views, size);
    return fit && fit->rms_px <= limits.max_error_px;
  };
  if (spec.squares_x != spec.squares_y) {
    BoardSpec swapped = spec;
    std::swap(swapped.squares_x, swapped.squares_y);
    if (fits(swapped))
      return fmt::format(" — rows and columns are swapped: the board is {}x{} (columns x rows), give --squares {}x{}",
                         swapped.squares_x, swapped.squares_y, swapped.squares_x, swapped.squares_y);
  }
  if (spec.squares_y % 2 == 0) {
    BoardSpec other_layout = spec;
    other_layout.legacy = !spec.legacy;
    if (fits(other_layout))
      return spec.legacy ? std::string(" — the board has today's layout: leave out --legacy")
                         : std::string(" — the board has the legacy layout (OpenCV before 4.6): give --legacy");
  }
  if (!found) {
    // A census first, on at most 20 frames spread over the views: only a
    // dictionary that finds the board in one of them is fitted (a camera
    // that never saw any board costs 20 detections a dictionary, not a
    // recording's worth).
    std::vector<cv::Mat> sample;
    const std::size_t step = std::max<std::size_t>(1, frames.size() / 20);
    for (std::size_t i = 0; i < frames.size(); i += step) sample.push_back(frames[i]);
    for (const std::string& name : dictionary_names()) {
      if (name == spec.dictionary) continue;
      BoardSpec other = spec;
      other.dictionary = name;
      auto alternative = CalibrationBoard::create(other);
      if (!alternative) continue;
      const bool seen = std::any_of(sample.begin(), sample.end(), [&](const cv::Mat& frame) {
        return alternative->usable(alternative->detect(frame), limits.min_corners);
      });
      if (seen && fits(other)) {
        // DICT_NxN_50, _100, _250 and _1000 begin with the same markers: a
        // board found with the smallest is of that family.
        const bool family = name.size() > 3 && name.compare(name.size() - 3, 3, "_50") == 0;
        return fmt::format(" — the markers are from {}{}: give --dictionary {}", name,
                           family ? fmt::format(" (or {}_100, _250, _1000, which begin with the same markers)",
                                                name.substr(0, name.size() - 3))
                                  : std::string(),
                           name);
      }
    }
  }
  return "";
}

// A camera that films mirror-imaged (a webcam's mirror or "selfie"
// setting) shows a ChArUco board whose markers read as no marker at all:
// the board is found in its frames flipped left to right, not as filmed.
// A sample of at most 20 frames spread over the views is tried both ways;
// "" unless the flipped frames find the board usable in at least 2 of them
// and in more than twice as many as the frames as filmed.
std::string mirrored_camera(const CalibrationBoard& board, const CameraFrames& camera_frames,
                            const CalibrationLimits& limits, const std::string& camera) {
  const std::vector<cv::Mat>& frames = camera_frames.views;
  if (board.spec().kind != BoardKind::Charuco || frames.empty()) return "";
  const std::size_t step = std::max<std::size_t>(1, frames.size() / 20);
  int sampled = 0, as_filmed = 0, flipped = 0;
  cv::Mat mirror;
  for (std::size_t i = 0; i < frames.size(); i += step) {
    ++sampled;
    if (board.usable(board.detect(frames[i]), limits.min_corners)) ++as_filmed;
    cv::flip(frames[i], mirror, 1);
    if (board.usable(board.detect(mirror), limits.min_corners)) ++flipped;
  }
  if (flipped < 2 || flipped <= 2 * as_filmed) return "";
  if (camera_frames.flipped)
    return fmt::format("{} camera: its images are not mirrored: the board is found in {} of {} frames sampled from "
                       "the views as filmed, in {} flipped left to right by --mirror; leave {} out of --mirror",
                       camera, flipped, sampled, as_filmed, camera);
  return fmt::format(
      "{} camera: its images are mirrored (left–right flipped, a webcam's mirror or selfie setting): the board is "
      "found in {} of {} frames sampled from the views when they are flipped left to right, in {} as filmed; give "
      "--mirror {} to calibrate its images flipped, and switch the camera's mirroring off (or flip its frames) for "
      "the station (docs/calibration.md, \"A mirrored camera\")",
      camera, flipped, sampled, as_filmed, camera);
}

// The intrinsics of camera `i`, from elsewhere or from its views (`observed`,
// every views frame); nothing (and a problem) when they cannot be had.
std::optional<CameraModel> intrinsics_of(const CalibrationBoard& board, const CameraFrames& frames,
                                         const FrameObservations& observed, cv::Size size,
                                         const CalibrationLimits& limits, CameraReport& r,
                                         std::vector<std::string>& problems, std::vector<std::string>& warnings) {
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
    r.intrinsics = given;
    r.intrinsics_accepted = true;
    return given;
  }
  const auto views = distinct_views(observed, limits, r);
  if (static_cast<int>(views.size()) < limits.min_views) {
    // Too few views, or none: a mirrored camera is named before the board.
    if (std::string mirrored = mirrored_camera(board, frames, limits, r.name); !mirrored.empty()) {
      problems.push_back(std::move(mirrored));
      return std::nullopt;
    }
  }
  if (r.frames_with_board == 0) {
    problems.push_back(fmt::format(
        "{} camera: the board was not found in any of the {} frames of the views ({}): hold the board ({}) whole in "
        "the {} camera's view, 1–3 m away and well lit, and check that --board, --squares, --square-mm, "
        "--marker-mm and --dictionary describe the printed board{}",
        r.name, r.frames,
        board.spec().kind == BoardKind::Charuco ? fmt::format("at most {} of its markers in a frame", r.max_markers)
                                                : std::string("no complete chessboard in any frame"),
        board.describe(), r.name, misdescribed_board(board, frames.views, size, limits, false)));
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
  r.sigma = fit->sigma;
  r.max_tilt_deg = fit->max_tilt_deg;
  r.covered_cells = covered_cells(views, size);
  fit->camera.image_width = size.width;
  fit->camera.image_height = size.height;
  r.intrinsics = fit->camera;
  if (r.rms_px > limits.max_error_px) {
    problems.push_back(fmt::format(
        "{} camera: reprojection error {:.2f} px RMS over {} views, more than {:.2f} px; worst views: {}: a blurred "
        "frame, a board that is not flat or moved during the exposure; record those poses again holding the board "
        "still (or allow more with --max-error){}",
        r.name, r.rms_px, r.views.size(), limits.max_error_px, worst_views(r),
        misdescribed_board(board, frames.views, size, limits, true)));
    return std::nullopt;
  }
  // Views that leave the intrinsics loose: named, with what would pin them.
  const double f = fit->camera.camera_matrix(0, 0);
  const double loose_f = std::max(r.sigma[0], r.sigma[1]) / f;
  const double loose_c = std::max(r.sigma[2] / size.width, r.sigma[3] / size.height);
  if (loose_f > limits.pinned_fraction || loose_c > limits.pinned_fraction) {
    std::vector<std::string> add;
    if (r.covered_cells != 0x1FF) add.push_back(fmt::format("with the board in the {}", r.coverage().substr(r.coverage().find("missing: ") + 9)));
    if (r.max_tilt_deg < 30) add.push_back(fmt::format("tilted 30–45° each way (the most tilted was {:.0f}°)", r.max_tilt_deg));
    if (static_cast<int>(views.size()) < 30) add.push_back(fmt::format("more of them ({} distinct now; 40 or more)", views.size()));
    if (!add.empty() && add.front().back() == ')') add.front().pop_back();
    std::string what;
    for (std::size_t i = 0; i < add.size(); ++i) what += (i ? "; " : "") + add[i];
    warnings.push_back(fmt::format(
        "{} camera: its views do not pin its intrinsics (fx ± {:.1f} px, cx ± {:.1f}, cy ± {:.1f} px at 1 σ): add "
        "views {}",
        r.name, r.sigma[0], r.sigma[2], r.sigma[3], what.empty() ? "at new poses" : what));
  }
  const auto bad = intrinsics_problems(r.name, fit->camera, limits.rules);
  problems.insert(problems.end(), bad.begin(), bad.end());
  if (!bad.empty()) return std::nullopt;
  r.intrinsics_accepted = true;
  return fit->camera;
}

std::string vec(const Eigen::Vector3d& v) { return fmt::format("({:.0f}, {:.0f}, {:.0f})", v.x(), v.y(), v.z()); }

// The board's pose in the frontal camera from its pose in the lateral one.
BoardPose via_relative(const BoardPose& lateral, const RelativePose& rel) {
  return {rel.R.transpose() * lateral.R, rel.R.transpose() * (lateral.t - rel.t)};
}
BoardPose to_lateral(const BoardPose& frontal, const RelativePose& rel) {
  return {rel.R * frontal.R, rel.R * frontal.t + rel.t};
}

}  // namespace

std::string CameraReport::seen() const {
  if (intrinsics_given) return "intrinsics given";
  return fmt::format("board in {} of {} frames, {} with enough corners, {} distinct views, {:.0f} corners on average",
                     frames_with_board, frames, frames_usable, distinct_views, mean_corners);
}

std::string CameraReport::colours() const {
  if (frames_white_on_black == 0) return "black on white";
  if (frames_black_on_white == 0) return "white on black (inverted)";
  return fmt::format("black on white in {} frames, white on black (inverted) in {}", frames_black_on_white,
                     frames_white_on_black);
}

std::string CameraReport::coverage() const {
  static constexpr const char* kCells[9] = {"top left",    "top",    "top right",    "left", "centre",
                                            "right",       "bottom left", "bottom", "bottom right"};
  int covered = 0;
  std::string missing;
  for (int i = 0; i < 9; ++i) {
    if (covered_cells & (1u << i)) {
      ++covered;
    } else {
      missing += fmt::format("{}{}", missing.empty() ? "" : ", ", kCells[i]);
    }
  }
  return fmt::format("{} of 9 ninths of the image{}", covered, missing.empty() ? "" : " (missing: " + missing + ")");
}

StationCalibration calibrate_station(const CalibrationBoard& board, const std::array<CameraFrames, 2>& frames,
                                     cv::Size image_size, const PlacementSpec& placement,
                                     const CalibrationLimits& limits) {
  StationCalibration out;
  CalibrationReport& report = out.report;
  report.board = board.describe();
  std::array<FrameObservations, 2> observed;
  std::array<std::optional<CameraModel>, 2> intrinsics;
  for (int i = 0; i < 2; ++i) {
    report.cameras[i].name = kNames[i];
    observed[i] = observe_frames(board, frames[i].views, limits, report.cameras[i]);
    intrinsics[i] = intrinsics_of(board, frames[i], observed[i], image_size, limits, report.cameras[i],
                                  report.problems, report.warnings);
  }

  // The rig: the lateral camera from the frontal, from every frame both saw
  // the board in.
  std::optional<RelativePose> relative;
  // The placement recording's frames are shared views too (both cameras
  // see the board there by design), and usually the best of them.
  std::array<FrameObservations, 2> shared;
  if (frames[0].views_taken_together && frames[1].views_taken_together) shared = observed;
  // Equal lengths, so that the placement's frames pair with each other.
  for (auto& s : shared) s.resize(std::max(shared[0].size(), shared[1].size()));
  if (!frames[0].placement.empty() && frames[0].placement.size() == frames[1].placement.size())
    for (int i = 0; i < 2; ++i) {
      CameraReport scratch;
      for (auto& o : observe_frames(board, frames[i].placement, limits, scratch)) shared[i].push_back(std::move(o));
    }
  report.shared_views = count_shared_views(shared[0], shared[1]);
  if (intrinsics[0] && intrinsics[1] && report.shared_views > 0) {
    auto fitted = fit_relative_pose(board, {*intrinsics[0], *intrinsics[1]}, {&shared[0], &shared[1]},
                                    limits.min_shared_views, image_size);
    if (fitted) {
      relative = *fitted;
      report.relative_rms_px = fitted->rms_px;
      if (fitted->rms_px > limits.max_error_px)
        report.warnings.push_back(fmt::format(
            "the frames both cameras saw the board in reproject with {:.2f} px RMS (more than {:.2f}): the "
            "cameras' frames were not taken at the same instant while the board moved, or the intrinsics are loose",
            fitted->rms_px, limits.max_error_px));
    } else {
      report.warnings.push_back(fmt::format("the relative pose is from the placement alone: {}", fitted.error().message));
    }
  }

  // The world frame: the placement recording, or a still stretch of the views.
  std::array<std::vector<cv::Mat>, 2> placement_frames = {frames[0].placement, frames[1].placement};
  report.world_from = "the placement recording";
  // (Not looked for in the views when a camera has no intrinsics: there is
  // nothing to place, and the refusal above says why.)
  if (placement_frames[0].empty() && placement_frames[1].empty()) {
    if (!intrinsics[0] || !intrinsics[1]) return out;
    std::vector<const FrameObservations*> needed;
    if (relative) {
      needed = {&observed[0]};
    } else {
      needed = {&observed[0], &observed[1]};
    }
    // still_px is for a 320-pixel-wide image: the same motion in the world
    // is more pixels at a higher resolution.
    const double still_px = limits.still_px * image_size.width / 320.0;
    const auto still = find_still_stretch(needed, still_px);
    if (!still) {
      report.problems.push_back(fmt::format(
          "no placement: the board was never still (moving less than {:.1f} px a frame) for two frames in the {} "
          "view{} of the views: record the board where the subject will stand (--placement), or hold it still "
          "there for a second at the end of the views",
          still_px, relative ? "frontal camera's" : "two cameras'", relative ? "" : "s"));
      return out;
    }
    // One frame, the middle of the stretch: a hand-held board still moves a
    // little, and corners pooled over frames would not be of one pose.
    const auto middle = static_cast<std::size_t>((still->first + still->last) / 2);
    for (int i = 0; i < 2; ++i) placement_frames[i].push_back(frames[i].views[middle]);
    report.world_from = fmt::format("views frame {} (frames {}–{}: the board still within {:.2f} px)", middle,
                                    still->first, still->last, still->motion_px);
  }

  std::array<std::optional<BoardPose>, 2> poses;
  for (int i = 0; i < 2; ++i) {
    if (!intrinsics[i] || placement_frames[i].empty()) continue;
    auto pose = locate_board(board, *intrinsics[i], placement_frames[i], limits, report.cameras[i]);
    if (!pose) {
      // With the relative pose, one camera's view of the placement is enough.
      if (!relative) report.problems.push_back(pose.error().message);
      continue;
    }
    // With the relative pose, the lateral camera's placement is only
    // compared with the rig's (the world frame is the frontal's).
    if (report.cameras[i].placement_rms_px > limits.max_error_px && (!relative || i == 0))
      report.problems.push_back(fmt::format(
          "{} camera: the placement board reprojects with {:.2f} px RMS, more than {:.2f} px: the board moved during "
          "the placement recording, or is not flat; record the placement again with the board still",
          kNames[i], report.cameras[i].placement_rms_px, limits.max_error_px));
    poses[i] = *pose;
  }
  if (!intrinsics[0] || !intrinsics[1]) return out;
  if (relative) {
    const bool frontal_placed = poses[0].has_value();
    if (!poses[0] && poses[1]) poses[0] = via_relative(*poses[1], *relative);
    if (!poses[0]) {
      report.problems.push_back(fmt::format(
          "neither camera found the placement board (with at least {} corners): place the board where the "
          "subject will stand so that the cameras see it whole, and record the placement again",
          limits.min_corners));
      return out;
    }
    if (poses[1] && frontal_placed) {
      // The lateral camera's own view of the placement against the rig's: the
      // world frame's accuracy, apart from the rig's.
      const BoardPose expected = to_lateral(*poses[0], *relative);
      report.placement_disagreement_deg = degrees(Eigen::AngleAxisd(expected.R * poses[1]->R.transpose()).angle());
      report.placement_disagreement_mm =
          ((-expected.R.transpose() * expected.t) - (-poses[1]->R.transpose() * poses[1]->t)).norm();
    }
    poses[1] = to_lateral(*poses[0], *relative);
  } else if (!poses[0] || !poses[1]) {
    return out;
  }

  const WorldInBoard world = world_frame(board, *poses[0], placement);
  CameraRig& rig = out.rig;
  rig.frontal = place(*intrinsics[0], *poses[0], world);
  rig.lateral = place(*intrinsics[1], *poses[1], world);
  if (!relative && board.spec().kind == BoardKind::Chessboard && rig.lateral.centre_in_world().z() < 0)
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
  report.baseline_mm = (report.cameras[0].centre - report.cameras[1].centre).norm();
  report.axis_angle_deg =
      degrees(std::acos(std::clamp(report.cameras[0].axis.dot(report.cameras[1].axis), -1.0, 1.0)));
  const Eigen::Vector3d flat[2] = {report.cameras[0].axis.cwiseProduct(Eigen::Vector3d(1, 0, 1)),
                                   report.cameras[1].axis.cwiseProduct(Eigen::Vector3d(1, 0, 1))};
  report.horizontal_axis_angle_deg =
      flat[0].norm() < 1e-6 || flat[1].norm() < 1e-6
          ? 0.0
          : degrees(std::acos(std::clamp(flat[0].normalized().dot(flat[1].normalized()), -1.0, 1.0)));
  for (auto& p : extrinsics_problems(rig, limits.rules)) report.problems.push_back(std::move(p));
  if (limits.baseline_mm > 0 && std::abs(report.baseline_mm / limits.baseline_mm - 1) > limits.baseline_tolerance)
    report.problems.push_back(fmt::format(
        "the cameras are {:.0f} mm apart by the calibration but {:.0f} mm by --baseline-mm: every distance scales "
        "with the board's squares, so they are {:.1f} mm, not {} mm as given: measure a square and give "
        "--square-mm (and --marker-mm) as measured",
        report.baseline_mm, limits.baseline_mm, board.spec().square_mm * limits.baseline_mm / report.baseline_mm,
        board.spec().square_mm));
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
    if (c.frames_with_board > 0) s += fmt::format("  markers: {}\n", c.colours());
    if (c.intrinsics && !c.intrinsics_given) {
      const CameraModel& k = *c.intrinsics;
      s += fmt::format("  intrinsics: {:.3f} px RMS over {} views, {}, most tilted view {:.0f}°\n", c.rms_px,
                       c.views.size(), c.coverage(), c.max_tilt_deg);
      s += fmt::format("    fx {:.1f} ± {:.1f}, fy {:.1f} ± {:.1f}, cx {:.1f} ± {:.1f}, cy {:.1f} ± {:.1f} px (1 σ)\n",
                       k.camera_matrix(0, 0), c.sigma[0], k.camera_matrix(1, 1), c.sigma[1], k.camera_matrix(0, 2),
                       c.sigma[2], k.camera_matrix(1, 2), c.sigma[3]);
      s += fmt::format("    k1 {:.4f} ± {:.4f}, k2 {:.4f} ± {:.4f}, p1 {:.5f} ± {:.5f}, p2 {:.5f} ± {:.5f}\n",
                       k.dist_coeffs[0], c.sigma[4], k.dist_coeffs[1], c.sigma[5], k.dist_coeffs[2], c.sigma[6],
                       k.dist_coeffs[3], c.sigma[7]);
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
  if (report.placed) {
    if (report.relative_rms_px > 0)
      s += fmt::format("rig: the lateral camera from the frontal fitted to {} frames both saw the board in, "
                       "{:.3f} px RMS; cameras {:.0f} mm apart\n",
                       report.shared_views, report.relative_rms_px, report.baseline_mm);
    else
      s += fmt::format("rig: each camera from its own view of the placement; cameras {:.0f} mm apart\n",
                       report.baseline_mm);
    s += fmt::format("world frame: from {}", report.world_from);
    if (report.placement_disagreement_deg >= 0)
      s += fmt::format("; the lateral camera's own view of it agrees with the rig within {:.2f}° and {:.0f} mm",
                       report.placement_disagreement_deg, report.placement_disagreement_mm);
    s += "\n";
    s += fmt::format("angle between the optical axes: {:.2f}° ({:.2f}° seen from above)\n", report.axis_angle_deg,
                     report.horizontal_axis_angle_deg);
  }
  for (const auto& w : report.warnings) s += fmt::format("warning: {}\n", w);
  for (const auto& p : report.problems) s += fmt::format("refused: {}\n", p);
  return s;
}

}  // namespace spinewatch
