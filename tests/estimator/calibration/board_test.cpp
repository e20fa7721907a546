// The calibration board: what a bad board description says, and that the
// corners found in the printed image are where the board says they are.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "spinewatch/estimator/calibration/board.hpp"

namespace spinewatch {
namespace {

std::string create_error(const BoardSpec& spec) {
  auto board = CalibrationBoard::create(spec);
  EXPECT_FALSE(board);
  return board ? std::string() : board.error().message;
}

TEST(CalibrationBoard, BadBoardsAreNamed) {
  EXPECT_EQ(create_error({.marker_mm = 150}), "board: marker size 150 mm must be positive and smaller than the square (150 mm)");
  EXPECT_EQ(create_error({.dictionary = "DICT_9X9_50"}), "board: unknown dictionary 'DICT_9X9_50' (DICT_4X4_50 … DICT_7X7_1000, DICT_ARUCO_ORIGINAL, DICT_APRILTAG_16h5, _25h9, _36h10, _36h11)");
  EXPECT_EQ(create_error({.squares_x = 2}), "board: 2x7 squares; give 3 to 40 squares each way");
  EXPECT_EQ(create_error({.squares_x = 12, .squares_y = 10}), "board: 12x10 squares need 60 markers but DICT_4X4_50 has 50");
  EXPECT_NE(create_error({.kind = BoardKind::Chessboard, .squares_x = 7, .squares_y = 7}).find("looks the same turned by 90°"),
            std::string::npos);
}

// Drawn, then found in the drawing (scaled down to camera-like sizes):
// the corners are at board_to_image of their board coordinates.
void expect_found_where_drawn(const BoardSpec& spec, double px_per_mm) {
  auto board = CalibrationBoard::create(spec);
  ASSERT_TRUE(board) << board.error().message;
  const double margin = 30;
  const cv::Mat image = board->draw(px_per_mm, margin);
  const BoardDetection found = board->detect(image);
  ASSERT_EQ(int(found.ids.size()), board->corner_count()) << board->describe();
  EXPECT_TRUE(board->usable(found, 8));
  const cv::Matx23d A = board->board_to_image(px_per_mm, margin);
  // A chessboard's corners may be numbered from either end (the board turned
  // by 180° looks the same); ChArUco's never are.
  std::vector<int> ids = found.ids;
  const cv::Point3f first = board->corner(ids.front());
  if (spec.kind == BoardKind::Chessboard &&
      cv::norm(found.pixels.front() - cv::Point2f(float(A(0, 0) * first.x + A(0, 2)), float(A(1, 1) * first.y + A(1, 2)))) > 5)
    std::reverse(ids.begin(), ids.end());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const cv::Point3f c = board->corner(ids[i]);
    const cv::Point2d expected(A(0, 0) * c.x + A(0, 2), A(1, 1) * c.y + A(1, 2));
    EXPECT_NEAR(found.pixels[i].x, expected.x, 0.15) << "corner " << ids[i];
    EXPECT_NEAR(found.pixels[i].y, expected.y, 0.15) << "corner " << ids[i];
  }
}

TEST(CalibrationBoard, CharucoCornersAreFoundWhereDrawn) { expect_found_where_drawn({}, 0.6); }

TEST(CalibrationBoard, ChessboardCornersAreFoundWhereDrawn) {
  expect_found_where_drawn({.kind = BoardKind::Chessboard, .squares_x = 8, .squares_y = 6, .square_mm = 100}, 0.5);
}

// A board printed with inverted colours (white markers on black squares,
// caliscope's default) is found without being told, and says so.
TEST(CalibrationBoard, InvertedBoardsAreFoundAndNamed) {
  auto board = CalibrationBoard::create({});
  ASSERT_TRUE(board);
  const cv::Mat image = board->draw(0.6, 30);
  cv::Mat inverted;
  cv::bitwise_not(image, inverted);
  const cv::Mat untouched = inverted.clone();
  const BoardDetection normal = board->detect(image), white = board->detect(inverted);
  EXPECT_EQ(cv::norm(inverted, untouched, cv::NORM_INF), 0) << "the caller's frame was changed";
  EXPECT_FALSE(normal.inverted);
  EXPECT_TRUE(white.inverted);
  EXPECT_EQ(int(white.ids.size()), board->corner_count());
  for (std::size_t i = 0; i < white.ids.size(); ++i) EXPECT_NEAR(cv::norm(white.pixels[i] - normal.pixels[i]), 0, 0.05);
  // Told the wrong colours first, it still finds the board.
  EXPECT_EQ(int(board->detect(image, true).ids.size()), board->corner_count());
}

// How far the corners found are from where a homography of the board's
// plane puts them (px RMS): small when the board's layout is the printed
// one, large when its corners are named after the wrong markers.
double off_the_plane(const CalibrationBoard& board, const cv::Mat& image) {
  const BoardDetection found = board.detect(image);
  if (found.ids.size() < 4) return INFINITY;
  std::vector<cv::Point2f> plane;
  for (int id : found.ids) plane.emplace_back(board.corner(id).x, board.corner(id).y);
  const cv::Mat H = cv::findHomography(plane, found.pixels, 0);
  std::vector<cv::Point2f> mapped;
  cv::perspectiveTransform(plane, mapped, H);
  double sum = 0;
  for (std::size_t i = 0; i < mapped.size(); ++i) sum += std::pow(cv::norm(mapped[i] - found.pixels[i]), 2);
  return std::sqrt(sum / double(mapped.size()));
}

// The legacy layout (OpenCV before 4.6, an even number of rows): drawn
// with a marker in the top left square, found where drawn; read with
// today's layout its corners are named after the wrong markers, and the
// other way round.
TEST(CalibrationBoard, LegacyLayoutIsFoundWhereDrawn) {
  const BoardSpec legacy{.squares_x = 5, .squares_y = 6, .square_mm = 150, .marker_mm = 115, .legacy = true};
  expect_found_where_drawn(legacy, 0.6);
  auto old_board = CalibrationBoard::create(legacy);
  BoardSpec today = legacy;
  today.legacy = false;
  auto new_board = CalibrationBoard::create(today);
  ASSERT_TRUE(old_board && new_board);
  const cv::Mat old_image = old_board->draw(0.6, 30), new_image = new_board->draw(0.6, 30);
  // The top left square: white with a marker in the legacy layout, black today.
  const cv::Point inside(int(30 * 0.6 + 5), int(30 * 0.6 + 5));
  EXPECT_EQ(old_image.at<std::uint8_t>(inside), 255);
  EXPECT_EQ(new_image.at<std::uint8_t>(inside), 0);
  EXPECT_LT(off_the_plane(*old_board, old_image), 0.2);
  EXPECT_LT(off_the_plane(*new_board, new_image), 0.2);
  EXPECT_GT(off_the_plane(*new_board, old_image), 2.0);
  EXPECT_GT(off_the_plane(*old_board, new_image), 2.0);
  // An odd number of rows is the same in both.
  auto odd = CalibrationBoard::create({.squares_x = 4, .squares_y = 5, .square_mm = 150, .marker_mm = 115, .legacy = true});
  ASSERT_TRUE(odd);
  EXPECT_EQ(int(odd->detect(CalibrationBoard::create({.squares_x = 4, .squares_y = 5, .square_mm = 150, .marker_mm = 115})
                                ->draw(0.6, 30))
                    .ids.size()),
            odd->corner_count());
}

// AprilTag and the original ArUco dictionaries.
TEST(CalibrationBoard, AprilTagAndOriginalArucoBoardsAreFound) {
  for (const char* dictionary : {"DICT_APRILTAG_16h5", "DICT_APRILTAG_25h9", "DICT_APRILTAG_36h11", "DICT_ARUCO_ORIGINAL"})
    expect_found_where_drawn({.squares_x = 4, .squares_y = 5, .square_mm = 150, .marker_mm = 115, .dictionary = dictionary},
                             0.6);
  EXPECT_EQ(create_error({.squares_x = 8, .squares_y = 8, .dictionary = "DICT_APRILTAG_16h5"}),
            "board: 8x8 squares need 32 markers but DICT_APRILTAG_16h5 has 30");
}

TEST(CalibrationBoard, TooFewOrCollinearCornersAreNotUsable) {
  auto board = CalibrationBoard::create({});
  ASSERT_TRUE(board);
  BoardDetection row;  // the first row of inner corners only
  for (int i = 0; i < 4; ++i) {
    row.ids.push_back(i);
    row.pixels.emplace_back(float(10 * i), 0.f);
  }
  EXPECT_FALSE(board->usable(row, 3));
  EXPECT_FALSE(board->usable(row, 8));
}

}  // namespace
}  // namespace spinewatch
