#include "spinewatch/estimator/calibration/board.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace spinewatch {
namespace {

struct NamedDictionary {
  const char* name;
  cv::aruco::PREDEFINED_DICTIONARY_NAME id;
};
constexpr std::array<NamedDictionary, 21> kDictionaries = {{
    {"DICT_4X4_50", cv::aruco::DICT_4X4_50},     {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
    {"DICT_4X4_250", cv::aruco::DICT_4X4_250},   {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
    {"DICT_5X5_50", cv::aruco::DICT_5X5_50},     {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
    {"DICT_5X5_250", cv::aruco::DICT_5X5_250},   {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
    {"DICT_6X6_50", cv::aruco::DICT_6X6_50},     {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
    {"DICT_6X6_250", cv::aruco::DICT_6X6_250},   {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
    {"DICT_7X7_50", cv::aruco::DICT_7X7_50},     {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
    {"DICT_7X7_250", cv::aruco::DICT_7X7_250},   {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
    {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
    {"DICT_APRILTAG_16h5", cv::aruco::DICT_APRILTAG_16h5},
    {"DICT_APRILTAG_25h9", cv::aruco::DICT_APRILTAG_25h9},
    {"DICT_APRILTAG_36h10", cv::aruco::DICT_APRILTAG_36h10},
    {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11},
}};

// Fewer corners than this in the colours tried first: the other colours are tried too.
constexpr int kEnoughCorners = 4;

// Images up to this wide get the second corner refinement (detect_charuco).
constexpr int kRefineUpToWidth = 640;

// The chessboard's inner corners, row by row (the order in which
// cv::findChessboardCorners reports them).
std::vector<cv::Point3f> grid_corners(const BoardSpec& spec) {
  std::vector<cv::Point3f> corners;
  for (int y = 1; y < spec.squares_y; ++y)
    for (int x = 1; x < spec.squares_x; ++x)
      corners.emplace_back(float(x * spec.square_mm), float(y * spec.square_mm), 0.f);
  return corners;
}

// OpenCV 4.6's CharucoBoard has no legacy layout (setLegacyPattern came
// with 4.8): the markers are moved to the other squares here, keeping
// OpenCV's coordinates (x right, y down the printed board, ids row by row
// from the top left) and each marker's place within its square, and the
// corners' nearest markers, which interpolateCornersCharuco reads, are
// worked out again for the new places.
void make_legacy(cv::aruco::CharucoBoard& board, const BoardSpec& spec) {
  const float square = float(spec.square_mm);
  // Marker 0 of OpenCV's layout sits in square (1, 0): its offset in a square.
  const cv::Point3f offset = board.objPoints[0][0] - cv::Point3f(square, 0, 0);
  std::vector<std::vector<cv::Point3f>> markers;
  for (int y = 0; y < spec.squares_y; ++y)
    for (int x = 0; x < spec.squares_x; ++x) {
      if ((x + y) % 2 != 0) continue;  // the black squares of the legacy layout (even rows)
      std::vector<cv::Point3f> corners;
      for (const cv::Point3f& c : board.objPoints[0])
        corners.push_back(c - board.objPoints[0][0] + offset + cv::Point3f(float(x) * square, float(y) * square, 0));
      markers.push_back(std::move(corners));
    }
  board.objPoints = markers;
  board.ids.resize(markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i) board.ids[i] = static_cast<int>(i);
  // Each corner's nearest markers (two inside the board, one at its edge)
  // and, of each, its nearest corner.
  board.nearestMarkerIdx.assign(board.chessboardCorners.size(), {});
  board.nearestMarkerCorners.assign(board.chessboardCorners.size(), {});
  for (std::size_t c = 0; c < board.chessboardCorners.size(); ++c) {
    const cv::Point3f& corner = board.chessboardCorners[c];
    std::vector<double> distance(markers.size());
    double nearest = INFINITY;
    for (std::size_t m = 0; m < markers.size(); ++m) {
      const cv::Point3f centre = (markers[m][0] + markers[m][2]) * 0.5f;
      distance[m] = cv::norm(centre - corner);
      nearest = std::min(nearest, distance[m]);
    }
    for (std::size_t m = 0; m < markers.size(); ++m) {
      if (distance[m] > nearest + 0.01 * square) continue;
      int closest = 0;
      for (int k = 1; k < 4; ++k)
        if (cv::norm(markers[m][std::size_t(k)] - corner) < cv::norm(markers[m][std::size_t(closest)] - corner))
          closest = k;
      board.nearestMarkerIdx[c].push_back(static_cast<int>(m));
      board.nearestMarkerCorners[c].push_back(closest);
    }
  }
}

}  // namespace

std::vector<std::string> dictionary_names() {
  std::vector<std::string> names;
  for (const auto& d : kDictionaries) names.emplace_back(d.name);
  return names;
}

Result<CalibrationBoard> CalibrationBoard::create(const BoardSpec& spec) {
  if (spec.squares_x < 3 || spec.squares_y < 3 || spec.squares_x > 40 || spec.squares_y > 40)
    return Error{fmt::format("board: {}x{} squares; give 3 to 40 squares each way", spec.squares_x, spec.squares_y)};
  if (!(spec.square_mm > 0) || spec.square_mm > 1000)
    return Error{fmt::format("board: square size {} mm is out of range (0, 1000]", spec.square_mm)};
  CalibrationBoard board;
  board.spec_ = spec;
  if (spec.kind == BoardKind::Chessboard) {
    if (spec.squares_x == spec.squares_y)
      return Error{fmt::format("board: a square chessboard ({}x{}) looks the same turned by 90°; use one with more "
                               "squares one way than the other",
                               spec.squares_x, spec.squares_y)};
    board.corners_ = grid_corners(spec);
    return board;
  }
  if (!(spec.marker_mm > 0) || spec.marker_mm >= spec.square_mm)
    return Error{fmt::format("board: marker size {} mm must be positive and smaller than the square ({} mm)",
                             spec.marker_mm, spec.square_mm)};
  const NamedDictionary* named = nullptr;
  for (const auto& d : kDictionaries)
    if (spec.dictionary == d.name) named = &d;
  if (!named) return Error{fmt::format("board: unknown dictionary '{}' (DICT_4X4_50 … DICT_7X7_1000, DICT_ARUCO_ORIGINAL, DICT_APRILTAG_16h5, _25h9, _36h10, _36h11)", spec.dictionary)};
  board.dictionary_ = cv::aruco::getPredefinedDictionary(named->id);
  const int markers = (spec.squares_x * spec.squares_y) / 2;
  if (markers > board.dictionary_->bytesList.rows)
    return Error{fmt::format("board: {}x{} squares need {} markers but {} has {}", spec.squares_x, spec.squares_y,
                             markers, spec.dictionary, board.dictionary_->bytesList.rows)};
  board.charuco_ = cv::aruco::CharucoBoard::create(spec.squares_x, spec.squares_y, float(spec.square_mm),
                                                   float(spec.marker_mm), board.dictionary_);
  // Only an even number of rows differs (OpenCV's setLegacyPattern).
  if (spec.legacy && spec.squares_y % 2 == 0) make_legacy(*board.charuco_, spec);
  board.corners_ = board.charuco_->chessboardCorners;
  return board;
}

std::vector<cv::Point3f> CalibrationBoard::object_points(const std::vector<int>& ids) const {
  std::vector<cv::Point3f> points;
  points.reserve(ids.size());
  for (int id : ids) points.push_back(corner(id));
  return points;
}

Eigen::Vector3d CalibrationBoard::centre() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& c : corners_) sum += Eigen::Vector3d(c.x, c.y, c.z);
  return sum / double(corners_.size());
}

BoardDetection CalibrationBoard::detect(const cv::Mat& grey, bool inverted_first) const {
  BoardDetection found;
  if (spec_.kind == BoardKind::Chessboard) {
    const cv::Size pattern(spec_.squares_x - 1, spec_.squares_y - 1);
    std::vector<cv::Point2f> pixels;
    if (!cv::findChessboardCorners(grey, pattern, pixels, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
      return found;
    // Small images: a small search window, or neighbouring corners pull.
    cv::cornerSubPix(grey, pixels, {3, 3}, {-1, -1},
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.001));
    found.pixels = std::move(pixels);
    for (int i = 0; i < corner_count(); ++i) found.ids.push_back(i);
    return found;
  }
  // A board printed with inverted colours has white markers on black
  // squares: the same board to the geometry, found by looking for the
  // markers in the inverted image. Tried second, when the colours tried
  // first gave too few corners (a camera that never sees the board pays
  // for both).
  BoardDetection best = detect_charuco(grey, inverted_first);
  if (static_cast<int>(best.ids.size()) >= kEnoughCorners) return best;
  BoardDetection other = detect_charuco(grey, !inverted_first);
  if (other.ids.size() > best.ids.size() || (other.ids.size() == best.ids.size() && other.markers > best.markers))
    return other;
  return best;
}

BoardDetection CalibrationBoard::detect_charuco(const cv::Mat& grey, bool inverted) const {
  BoardDetection found;
  found.inverted = inverted;
  // A new image for the inverted colours: never the caller's frame.
  cv::Mat image;
  if (inverted)
    cv::bitwise_not(grey, image);
  else
    image = grey;
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  auto params = cv::aruco::DetectorParameters::create();
  // The corners that count are the chessboard's, refined by
  // interpolateCornersCharuco; the markers only identify them.
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_NONE;
  cv::aruco::detectMarkers(image, dictionary_, marker_corners, marker_ids, params);
  // Markers of the dictionary that are not on this board (another board in
  // view, or the wrong --squares) are left out.
  std::vector<std::vector<cv::Point2f>> on_board;
  std::vector<int> on_board_ids;
  for (std::size_t i = 0; i < marker_ids.size(); ++i)
    if (marker_ids[i] < static_cast<int>(charuco_->ids.size())) {
      on_board.push_back(marker_corners[i]);
      on_board_ids.push_back(marker_ids[i]);
    }
  found.markers = static_cast<int>(on_board_ids.size());
  if (on_board_ids.empty()) return found;
  cv::aruco::interpolateCornersCharuco(on_board, on_board_ids, image, charuco_, found.pixels, found.ids);
  // interpolateCornersCharuco refines each corner only within the gap
  // between it and the nearest marker, a pixel or two at this station's
  // resolution, and stops at 0.1 px: its corners keep up to half a pixel
  // of the markers' outline bias. Refined again on the chessboard corner
  // itself in a 5×5 window (the best of 3×3, 5×5 and 7×7 on the phantom's
  // boards: docs/calibration.md, "How it is tested"). A saddle point is one
  // in either colours. Only at the station's low resolutions: at 1280×720
  // OpenCV's own window is several pixels wide, and a second 5×5 pass on
  // real webcam footage pulled the corners off (caliscope's cam_1: fx 816
  // against OpenCV's own 756 ± 28 on the same frames; docs/calibration.md,
  // "The shared caliscope session").
  if (!found.pixels.empty() && grey.cols <= kRefineUpToWidth)
    cv::cornerSubPix(grey, found.pixels, {2, 2}, {-1, -1},
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.001));
  return found;
}

bool CalibrationBoard::usable(const BoardDetection& detection, int min_corners) const {
  if (static_cast<int>(detection.ids.size()) < min_corners) return false;
  // Not all on one row or column of the board (the pose would be undetermined).
  const cv::Point3f& first = corner(detection.ids.front());
  bool other_x = false, other_y = false;
  for (int id : detection.ids) {
    other_x |= corner(id).x != first.x;
    other_y |= corner(id).y != first.y;
  }
  if (!other_x || !other_y) return false;
  if (spec_.kind == BoardKind::Charuco) return !cv::aruco::testCharucoCornersCollinear(charuco_, detection.ids);
  return true;
}

cv::Matx23d CalibrationBoard::board_to_image(double px_per_mm, double margin_mm) const {
  const double m = margin_mm * px_per_mm;
  // Pixel centres at integer coordinates: board x = 0 is the left edge of
  // the squares, i.e. pixel coordinate m − 0.5.
  return {px_per_mm, 0, m - 0.5, 0, px_per_mm, m - 0.5};
}

cv::Mat CalibrationBoard::draw(double px_per_mm, double margin_mm) const {
  const cv::Size2d board = size_mm();
  const int margin = static_cast<int>(std::lround(margin_mm * px_per_mm));
  const cv::Size squares(static_cast<int>(std::lround(board.width * px_per_mm)),
                         static_cast<int>(std::lround(board.height * px_per_mm)));
  cv::Mat image(squares.height + 2 * margin, squares.width + 2 * margin, CV_8U, cv::Scalar(255));
  if (spec_.kind == BoardKind::Charuco && !(spec_.legacy && spec_.squares_y % 2 == 0)) {
    cv::Mat inner;
    charuco_->draw(squares, inner, 0, 1);
    inner.copyTo(image(cv::Rect(margin, margin, squares.width, squares.height)));
    return image;
  }
  if (spec_.kind == BoardKind::Charuco) {
    // The legacy layout, drawn here (OpenCV 4.6 draws only its own): black
    // squares where there is no marker, each marker at its board place.
    const cv::Matx23d to_image = board_to_image(px_per_mm, margin_mm);
    auto pixel = [&](const cv::Point3f& p) {
      return cv::Point(int(std::lround(to_image(0, 0) * p.x + to_image(0, 2) + 0.5)),
                       int(std::lround(to_image(1, 1) * p.y + to_image(1, 2) + 0.5)));
    };
    const float square = float(spec_.square_mm);
    for (int y = 0; y < spec_.squares_y; ++y)
      for (int x = 0; x < spec_.squares_x; ++x)
        if ((x + y) % 2 != 0)
          cv::rectangle(image, cv::Rect(pixel({float(x) * square, float(y) * square, 0}),
                                        pixel({float(x + 1) * square, float(y + 1) * square, 0})),
                        cv::Scalar(0), cv::FILLED);
    for (std::size_t m = 0; m < charuco_->objPoints.size(); ++m) {
      const cv::Point top_left = pixel(charuco_->objPoints[m][0]);
      const int side = pixel(charuco_->objPoints[m][2]).x - top_left.x;
      cv::Mat marker;
      cv::aruco::drawMarker(dictionary_, charuco_->ids[m], side, marker, 1);
      marker.copyTo(image(cv::Rect(top_left.x, top_left.y, side, side)));
    }
    return image;
  }
  const double s = spec_.square_mm * px_per_mm;
  for (int y = 0; y < spec_.squares_y; ++y)
    for (int x = 0; x < spec_.squares_x; ++x)
      if ((x + y) % 2 == 0)
        cv::rectangle(image,
                      cv::Rect(cv::Point(margin + int(std::lround(x * s)), margin + int(std::lround(y * s))),
                               cv::Point(margin + int(std::lround((x + 1) * s)), margin + int(std::lround((y + 1) * s)))),
                      cv::Scalar(0), cv::FILLED);
  return image;
}

std::string CalibrationBoard::describe() const {
  if (spec_.kind == BoardKind::Chessboard)
    return fmt::format("chessboard {}x{} squares of {} mm ({}x{} inner corners)", spec_.squares_x, spec_.squares_y,
                       spec_.square_mm, spec_.squares_x - 1, spec_.squares_y - 1);
  return fmt::format("ChArUco {}x{} squares of {} mm, markers {} mm, {}{}", spec_.squares_x, spec_.squares_y,
                     spec_.square_mm, spec_.marker_mm, spec_.dictionary, spec_.legacy ? ", legacy layout" : "");
}

}  // namespace spinewatch
