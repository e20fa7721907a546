#pragma once
// A calibration board in front of the phantom's cameras (docs/phantom.md,
// "Calibration boards"): the printed board rendered into a calibrated
// camera — through its lens distortion, antialiased, over the empty scene,
// with the sensor's noise — at known poses, for testing `spinewatch
// calibrate` against the truth.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "spinewatch/estimator/calibration/board.hpp"
#include "spinewatch/estimator/camera_model.hpp"
#include "spinewatch/frames/result.hpp"

namespace spinewatch::phantom {

// Where the board is: X_world = R · X_board + t (mm). Board coordinates as
// CalibrationBoard's: x across, y down the printed face, z = 0 on it, the
// printed face towards −z.
struct BoardPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

// One camera's view of the board. The lens model is inverted once per
// sub-pixel sample here; render() then costs a homography per sample.
class BoardRenderer {
 public:
  BoardRenderer(const CalibrationBoard& board, const CameraModel& camera, cv::Size size, int supersample = 4);

  // The noise-free image (CV_8U): `background` (CV_8U, `size`) with the
  // board over it; its back where the camera sees the back. Not const:
  // the sample-sized images are kept from one render to the next (a
  // session renders dozens of poses; allocating 20 MB afresh for each was
  // a third of a calibration test under the sanitizers, all page faults).
  cv::Mat render(const BoardPose& pose, const cv::Mat& background);

 private:
  CameraModel camera_;
  cv::Size size_;
  double px_per_mm_;
  cv::Matx23d to_texture_;
  cv::Mat texture_;     // CV_32F, grey levels of the printed board as the camera sees them
  cv::Mat normalised_;  // CV_32FC2, per sub-pixel sample: undistorted normalised coordinates (NaN: none)
  // Per sub-pixel sample, reused by render(): texture coordinates, on the
  // board or not, the board's grey, the scene's.
  cv::Mat map_, on_board_, board_, scene_;
};

// A calibration session as an installer records it: the board held at
// poses in front of each camera in turn (both cameras record every frame;
// the other camera may see the board obliquely, or its back), then the
// board standing upright where the subject stands, turned halfway between
// the cameras, its centre `centre_height_mm` above the floor.
struct BoardSessionOptions {
  int views_per_camera = 20;
  int placement_frames = 4;
  double centre_height_mm = 1100;
  std::uint32_t seed = 1;
  double noise_sigma = 2.0;
  // Which cameras the held views are for: a camera left out never sees the
  // board held up (it may still see the placement).
  std::array<bool, 2> views_for = {true, true};
  // The placement board is hidden from these cameras (out of view).
  std::array<bool, 2> placement_seen = {true, true};
};

struct BoardSession {
  std::vector<BoardPose> views;  // frontal's poses first, then lateral's
  BoardPose placement;
};

// Poses spread over each camera's image, 1.5–2.5 m away, tilted 20–45° each way
// (deterministic for the seed).
BoardSession plan_board_session(const CameraRig& rig, const CalibrationBoard& board, const BoardSessionOptions& options);

// The frames of one recording (index: View), grey CV_8U with noise.
struct BoardFrames {
  std::array<std::vector<cv::Mat>, 2> grey;
};
BoardFrames render_board_views(const CameraRig& rig, const CalibrationBoard& board, const std::vector<BoardPose>& poses,
                               const std::array<bool, 2>& seen, std::uint32_t seed, double noise_sigma,
                               std::uint64_t first_frame = 0);

// A recording directory of those frames (YUYV 320×240, 30 fps, no
// calibration.yaml: calibrating is what the recording is for).
Status write_board_recording(const BoardFrames& frames, const std::filesystem::path& dir);

}  // namespace spinewatch::phantom
