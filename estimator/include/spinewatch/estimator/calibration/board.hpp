#pragma once
// The calibration board: a ChArUco board (a chessboard with ArUco markers
// in its white squares, so that every corner found has an identity even
// when the board is only partly in view) or a plain chessboard (every
// inner corner must be in view). Knows its corners' positions on the board
// and finds them in an image.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "spinewatch/frames/result.hpp"

namespace cv::aruco {
class CharucoBoard;
class Dictionary;
}  // namespace cv::aruco

namespace spinewatch {

enum class BoardKind { Charuco, Chessboard };

struct BoardSpec {
  BoardKind kind = BoardKind::Charuco;
  int squares_x = 5, squares_y = 7;  // squares across and down the printed board
  double square_mm = 150;
  double marker_mm = 115;            // ChArUco only
  std::string dictionary = "DICT_4X4_50";  // ChArUco only: OpenCV's predefined dictionary name
  // ChArUco only: the layout of OpenCV before 4.6, in which a board with an
  // even number of rows starts with a white square (a marker) at the top
  // left; the same as today's with an odd number.
  bool legacy = false;
};

// The names of the dictionaries a ChArUco board may use (OpenCV's
// predefined ones: DICT_4X4_50 … DICT_7X7_1000, DICT_ARUCO_ORIGINAL,
// DICT_APRILTAG_16h5, _25h9, _36h10, _36h11).
std::vector<std::string> dictionary_names();

// The corners of the board found in one image: corner ids (index into the
// board's corner list) and their pixel positions, sub-pixel refined.
struct BoardDetection {
  std::vector<int> ids;
  std::vector<cv::Point2f> pixels;
  int markers = 0;  // ArUco markers of the board found (ChArUco only)
  // The markers were found white on black (a board printed with inverted
  // colours, as caliscope prints its boards by default) — ChArUco only.
  bool inverted = false;
  bool empty() const { return ids.empty(); }
};

class CalibrationBoard {
 public:
  // Checks the spec: at least 3×3 squares, positive sizes, markers smaller
  // than squares, a known dictionary with enough markers.
  static Result<CalibrationBoard> create(const BoardSpec& spec);

  const BoardSpec& spec() const { return spec_; }
  int corner_count() const { return static_cast<int>(corners_.size()); }
  // Board coordinates (mm) of a corner: x along the squares_x direction,
  // y along squares_y (down the printed board), z = 0 on its face.
  const cv::Point3f& corner(int id) const { return corners_[static_cast<std::size_t>(id)]; }
  std::vector<cv::Point3f> object_points(const std::vector<int>& ids) const;
  // The centre of the corner grid, which is the centre of the printed squares.
  Eigen::Vector3d centre() const;
  // Width and height of the squares (mm).
  cv::Size2d size_mm() const { return {spec_.squares_x * spec_.square_mm, spec_.squares_y * spec_.square_mm}; }

  // ChArUco: the markers are looked for black on white and white on black
  // (`inverted_first` says which first: the colours the previous frame had);
  // the other colours are tried only when the first find too few corners.
  BoardDetection detect(const cv::Mat& grey, bool inverted_first = false) const;
  // Corners found that are enough to locate the board: at least
  // `min_corners`, not all on one line.
  bool usable(const BoardDetection& detection, int min_corners) const;

  // The board as printed (CV_8U, black on white) at `px_per_mm`, with a
  // white margin of `margin_mm` around the squares; and the affine map from
  // board millimetres (x, y) to that image's pixel coordinates.
  cv::Mat draw(double px_per_mm, double margin_mm) const;
  cv::Matx23d board_to_image(double px_per_mm, double margin_mm) const;

  std::string describe() const;  // "ChArUco 5×7 squares of 160 mm, markers 120 mm, DICT_4X4_50"

 private:
  CalibrationBoard() = default;
  BoardDetection detect_charuco(const cv::Mat& grey, bool inverted) const;

  BoardSpec spec_;
  std::vector<cv::Point3f> corners_;
  cv::Ptr<cv::aruco::Dictionary> dictionary_;
  cv::Ptr<cv::aruco::CharucoBoard> charuco_;
};

}  // namespace spinewatch
