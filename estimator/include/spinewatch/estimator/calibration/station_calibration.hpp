#pragma once
// Calibrating a station (docs/calibration.md): each camera's intrinsics
// from views of the board held at several poses, then both cameras in the
// world frame of docs/interfaces.md §1 from the board placed where the subject
// will stand. Pure computation on grey images; reading recordings and
// writing calibration.yaml is the caller's.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "spinewatch/estimator/calibration/board.hpp"
#include "spinewatch/estimator/calibration/rig_checks.hpp"
#include "spinewatch/estimator/camera_model.hpp"

namespace spinewatch {

// Where the board lies for the placement views, which fixes the world frame.
enum class Placement {
  // Upright (plumb) where the subject will stand, its face turned halfway
  // between the two cameras; the centre of its squares `centre_height_mm`
  // above the floor. Y is the board's edge that points up, the origin the
  // floor point below the board's centre.
  Upright,
  // Flat on the floor where the subject will stand: Y is the board's
  // normal, the origin the board's centre.
  Floor,
};

struct PlacementSpec {
  Placement kind = Placement::Upright;
  double centre_height_mm = 0;  // Upright only
};

// When a calibration is refused.
struct CalibrationLimits {
  int min_views = 8;                 // distinct board poses per camera for its intrinsics
  int min_corners = 8;               // corners in a view for it to count
  double max_error_px = 1.0;         // RMS reprojection error, per camera and of the placement
  double axis_tolerance_deg = 15.0;  // |angle between the optical axes seen from above − 90°|
  double distinct_px = 4.0;          // a view whose corners moved less than this since the last one kept is the same pose
  int min_shared_views = 5;          // frames both cameras see the board in, for the relative pose from them
  // No placement: the board moving less than this a frame (px at a
  // 320-pixel-wide image, scaled with the width) is placed.
  double still_px = 1.0;
  // A camera's views pin its intrinsics when the 1-σ of its focal length
  // is within this fraction of it and that of its centre within this
  // fraction of the image size; otherwise the report says what to add.
  double pinned_fraction = 0.01;
  double baseline_mm = 0;            // the cameras' distance measured with a tape (0: not given)
  double baseline_tolerance = 0.05;  // the calibrated distance must be within this fraction of it
  RigRules rules;                    // fy/fx, centre, distance and axes (rig_checks.hpp)
};

// One camera's input: grey frames of the board held at poses and of the
// board at its placement; or its intrinsics from elsewhere (load_intrinsics).
// The views of both cameras are taken together: frame i of one and frame i
// of the other show the board at the same instant (a recording's pairs, or
// synchronised videos), which is what the relative pose is fitted from.
// Without placement frames, a still stretch of the views places the board.
struct CameraFrames {
  std::vector<cv::Mat> views;
  std::vector<cv::Mat> placement;
  std::optional<CameraModel> intrinsics;
  // False when view i of this camera was not taken with view i of the
  // other (calibrate --live keeps each camera's own still frames): then
  // only the placement's frames are shared views.
  bool views_taken_together = true;
  // The frames were flipped left to right before they came here (calibrate
  // --mirror: a camera that films mirror-imaged); only changes what a
  // refusal suggests.
  bool flipped = false;
};

struct ViewError {
  int frame = 0;     // index into CameraFrames::views
  int corners = 0;
  double rms_px = 0;
  // Far worse than the others (over 3× their median and over 0.3 px at 320
  // pixels wide, scaled with the width: 1.2 px at 1280): not used.
  bool left_out = false;
};

// What one camera saw and what came of it.
struct CameraReport {
  std::string name;  // "frontal" / "lateral"
  bool intrinsics_given = false;
  int frames = 0;              // views frames
  int frames_with_board = 0;   // … where any corner of the board was found
  int frames_usable = 0;       // … with enough corners, not on one line
  int max_markers = 0;         // most ArUco markers of the board in one frame (ChArUco)
  int frames_black_on_white = 0, frames_white_on_black = 0;  // the markers' colours, frames with the board
  std::string colours() const;  // "black on white", "white on black (inverted)", or both with counts
  int distinct_views = 0;      // usable frames that are distinct poses
  std::vector<ViewError> views;  // the distinct poses used, with their errors
  double mean_corners = 0;
  double rms_px = 0;           // intrinsics: RMS reprojection error over all views
  std::optional<CameraModel> intrinsics;  // fitted or given; with image_width/height
  bool intrinsics_accepted = false;       // … and not refused (written on their own when the other camera is)
  std::array<double, 8> sigma{};          // 1-σ of fx fy cx cy k1 k2 p1 p2 (fitted only)
  unsigned covered_cells = 0;             // of a 3×3 grid over the image, the cells the views' corners fell in
  double max_tilt_deg = 0;                // the most tilted view
  std::string coverage() const;           // "6 of 9 ninths of the image (missing: top left, …)"
  int placement_frames = 0;
  int placement_frames_with_board = 0;
  int placement_corners = 0;   // distinct corners seen in the placement frames
  double placement_rms_px = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // camera centre, world (mm)
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();    // optical axis, world
  std::string seen() const;    // "board in 14 of 90 frames, 11 distinct views, 19 corners on average"
};

struct CalibrationReport {
  std::string board;  // CalibrationBoard::describe()
  std::array<CameraReport, 2> cameras;
  double axis_angle_deg = 0;
  // The same seen from above (the axes projected onto the floor): a front
  // and a side view are 90° apart this way even when both cameras look
  // down. What the orthogonality limit applies to.
  double horizontal_axis_angle_deg = 0;
  bool placed = false;  // the world frame was found (both cameras placed)
  // The rig's own accuracy: the lateral camera from the frontal, fitted to
  // every frame both saw the board in (0 views: from the placement alone).
  int shared_views = 0;
  double relative_rms_px = 0;
  double baseline_mm = 0;  // distance between the camera centres
  // The world frame: where it came from ("the placement recording",
  // "views frames 85–88, the board still within 0.6 px"), and — when the
  // relative pose is from the shared views and both cameras saw the
  // placement — how far the lateral camera's own placement disagrees.
  std::string world_from;
  double placement_disagreement_deg = -1, placement_disagreement_mm = -1;
  std::vector<std::string> problems;  // why it is refused; empty when accepted
  std::vector<std::string> warnings;
};

struct StationCalibration {
  CameraRig rig;
  CalibrationReport report;
  bool accepted() const { return report.problems.empty(); }
};

// `frames` index: 0 frontal, 1 lateral. `image_size`: the frames' size,
// written into the rig (image_width, image_height).
StationCalibration calibrate_station(const CalibrationBoard& board, const std::array<CameraFrames, 2>& frames,
                                     cv::Size image_size, const PlacementSpec& placement,
                                     const CalibrationLimits& limits);

// The report as an installer reads it: per camera what it saw, the error
// per view, the positions and the angle; then the problems, each with what
// to do.
std::string format_report(const CalibrationReport& report);

}  // namespace spinewatch
