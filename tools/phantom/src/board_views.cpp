#include "spinewatch/phantom/board_views.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "spinewatch/capture/recording.hpp"
#include "spinewatch/phantom/renderer.hpp"
#include "spinewatch/phantom/scenario.hpp"

namespace spinewatch::phantom {
namespace {

// A matte print under room light: black is not 0 nor white 255.
constexpr float kInk = 35, kPaper = 215, kBack = 150;
constexpr double kMarginMm = 20;  // white paper around the squares
constexpr int kWidth = 320, kHeight = 240;

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()).toRotationMatrix();
}

}  // namespace

BoardRenderer::BoardRenderer(const CalibrationBoard& board, const CameraModel& camera, cv::Size size, int supersample)
    : camera_(camera), size_(size) {
  // Texture fine enough that a sub-pixel sample never falls between its
  // texels even with the board close (2 px per mm).
  px_per_mm_ = 2.0;
  to_texture_ = board.board_to_image(px_per_mm_, kMarginMm);
  cv::Mat printed = board.draw(px_per_mm_, kMarginMm);
  printed.convertTo(texture_, CV_32F, (kPaper - kInk) / 255.0, kInk);

  // The lens model is inverted exactly at the pixel corners (u ± 0.5,
  // v ± 0.5: pixel centres at integer coordinates, OpenCV's convention) and
  // interpolated bilinearly to the samples in between: the inverse is
  // smooth enough that this is within 1e-3 px, at a sixteenth of the cost.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat corners(size.height + 1, size.width + 1, CV_32FC2);
  for (int y = 0; y <= size.height; ++y)
    for (int x = 0; x <= size.width; ++x) {
      const auto n = camera.normalised({x - 0.5, y - 0.5});
      corners.at<cv::Vec2f>(y, x) = n ? cv::Vec2f(float(n->x()), float(n->y())) : cv::Vec2f(nan, nan);
    }
  const cv::Size fine(size.width * supersample, size.height * supersample);
  normalised_.create(fine, CV_32FC2);
  for (int y = 0; y < fine.height; ++y)
    for (int x = 0; x < fine.width; ++x) {
      // Sample (x, y) lies at corner-grid coordinates ((x + 0.5)/s, (y + 0.5)/s).
      const double cx = (x + 0.5) / supersample, cy = (y + 0.5) / supersample;
      const int x0 = std::min(int(cx), size.width - 1), y0 = std::min(int(cy), size.height - 1);
      const float fx = float(cx - x0), fy = float(cy - y0);
      const cv::Vec2f top = corners.at<cv::Vec2f>(y0, x0) * (1 - fx) + corners.at<cv::Vec2f>(y0, x0 + 1) * fx;
      const cv::Vec2f bottom = corners.at<cv::Vec2f>(y0 + 1, x0) * (1 - fx) + corners.at<cv::Vec2f>(y0 + 1, x0 + 1) * fx;
      normalised_.at<cv::Vec2f>(y, x) = top * (1 - fy) + bottom * fy;
    }
}

cv::Mat BoardRenderer::render(const BoardPose& pose, const cv::Mat& background) {
  // Board to camera: x_cam = Rcb · X_board + tcb; a ray d = (x, y, 1) meets
  // the board's plane at (bx, by, 0) with (bx, by, 1) ∝ [r1 r2 tcb]⁻¹ d.
  const Eigen::Matrix3d Rcb = camera_.R * pose.R;
  const Eigen::Vector3d tcb = camera_.R * pose.t + camera_.t;
  Eigen::Matrix3d H;
  H << Rcb.col(0), Rcb.col(1), tcb;
  const Eigen::Matrix3d Hinv = H.inverse();
  // The printed face is towards the board's −z: seen when the camera is on that side.
  const bool front = (-Rcb.transpose() * tcb).z() < 0;

  const cv::Size fine = normalised_.size();
  cv::Mat& map = map_;
  cv::Mat& on_board = on_board_;
  map.create(fine, CV_32FC2);
  on_board.create(fine, CV_8U);
  on_board.setTo(0);
  // Every sample (1280 × 960 at 4× supersampling) runs this loop: the
  // matrices are read into scalars once and the rows through pointers, so
  // that no element access or small product is a call of its own (under
  // the sanitizers they were most of a calibration test's time). The sums
  // are Eigen's, in its order: the images are the same bytes as before.
  const double h00 = Hinv(0, 0), h01 = Hinv(0, 1), h02 = Hinv(0, 2), h10 = Hinv(1, 0), h11 = Hinv(1, 1),
               h12 = Hinv(1, 2), h20 = Hinv(2, 0), h21 = Hinv(2, 1), h22 = Hinv(2, 2);
  const double a00 = to_texture_(0, 0), a02 = to_texture_(0, 2), a11 = to_texture_(1, 1), a12 = to_texture_(1, 2);
  const double u_max = texture_.cols - 0.5, v_max = texture_.rows - 0.5;
  for (int y = 0; y < fine.height; ++y) {
    const cv::Vec2f* normalised = normalised_.ptr<cv::Vec2f>(y);
    cv::Vec2f* mapped = map.ptr<cv::Vec2f>(y);
    std::uint8_t* inside = on_board.ptr<std::uint8_t>(y);
    for (int x = 0; x < fine.width; ++x) {
      mapped[x] = cv::Vec2f(-1e6f, -1e6f);
      const double nx = normalised[x][0], ny = normalised[x][1];
      if (std::isnan(nx)) continue;
      const double bz = h20 * nx + h21 * ny + h22;
      if (bz <= 0) continue;  // the plane is behind the camera along this ray
      const double bx = (h00 * nx + h01 * ny + h02) / bz, by = (h10 * nx + h11 * ny + h12) / bz;
      const double u = a00 * bx + a02, v = a11 * by + a12;
      if (u < -0.5 || v < -0.5 || u > u_max || v > v_max) continue;
      mapped[x] = cv::Vec2f(float(u), float(v));
      inside[x] = 255;
    }
  }
  if (front) {
    cv::remap(texture_, board_, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  } else {
    board_.create(fine, CV_32F);
    board_.setTo(kBack);
  }
  cv::Mat grey;
  background.convertTo(grey, CV_32F);
  cv::resize(grey, scene_, fine, 0, 0, cv::INTER_NEAREST);
  board_.copyTo(scene_, on_board);
  // Average the samples of each pixel (antialiasing), then a slight lens blur.
  cv::Mat image;
  cv::resize(scene_, image, size_, 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(image, image, {3, 3}, 0.6);
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

BoardSession plan_board_session(const CameraRig& rig, const CalibrationBoard& board, const BoardSessionOptions& options) {
  BoardSession session;
  std::seed_seq seq{options.seed, 11u};
  std::mt19937 rng(seq);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d centre_b = board.centre();
  const bool whole = board.spec().kind == BoardKind::Chessboard;  // a chessboard is found only whole
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  for (int c = 0; c < 2; ++c) {
    if (!options.views_for[static_cast<std::size_t>(c)]) continue;
    const CameraModel& cam = *cams[c];
    for (int k = 0; k < options.views_per_camera; ++k) {
      // Aim at a 3×3 grid over the image, cycling, near and far.
      const double spread = whole ? 0.12 : 0.25;
      const double fu = 0.5 + spread * double(k % 3 - 1), fv = 0.5 + spread * double((k / 3) % 3 - 1);
      const double distance = (whole ? 2200 : 1500) + 1000 * unit(rng);
      const Eigen::Vector2d pixel(fu * kWidth, fv * kHeight);
      const Eigen::Vector3d at = cam.centre_in_world() + distance * cam.ray_through(pixel);
      // Facing the camera (board axes along the camera's), then tilted
      // 15–35° each way, the four combinations of signs in turn (what pins
      // the focal length and principal point down), and turned a little.
      const double tilt_x = ((k % 2) ? 1 : -1) * (15 + 20 * unit(rng));
      const double tilt_y = (((k / 2) % 2) ? 1 : -1) * (15 + 20 * unit(rng));
      const double roll = -15 + 30 * unit(rng);
      const Eigen::Matrix3d in_camera = rotation(Eigen::Vector3d::UnitX(), tilt_x) *
                                        rotation(Eigen::Vector3d::UnitY(), tilt_y) *
                                        rotation(Eigen::Vector3d::UnitZ(), roll);
      BoardPose pose;
      pose.R = cam.R.transpose() * in_camera;
      pose.t = at - pose.R * centre_b;
      session.views.push_back(pose);
    }
  }
  // Upright at the origin, its printed face towards the bisector of the
  // two cameras' directions (horizontal), the board's top up.
  const Eigen::Vector3d to_frontal = rig.frontal.centre_in_world().cwiseProduct(Eigen::Vector3d(1, 0, 1)).normalized();
  const Eigen::Vector3d to_lateral = rig.lateral.centre_in_world().cwiseProduct(Eigen::Vector3d(1, 0, 1)).normalized();
  const Eigen::Vector3d facing = (to_frontal + to_lateral).normalized();  // towards the viewers
  const Eigen::Vector3d z = -facing, y = -Eigen::Vector3d::UnitY(), x = y.cross(z);
  session.placement.R.col(0) = x;
  session.placement.R.col(1) = y;
  session.placement.R.col(2) = z;
  session.placement.t = Eigen::Vector3d(0, options.centre_height_mm, 0) - session.placement.R * centre_b;
  return session;
}

BoardFrames render_board_views(const CameraRig& rig, const CalibrationBoard& board, const std::vector<BoardPose>& poses,
                               const std::array<bool, 2>& seen, std::uint32_t seed, double noise_sigma,
                               std::uint64_t first_frame) {
  BoardFrames frames;
  const SensorModel sensor(seed, noise_sigma, 0.0);
  const CameraModel* cams[2] = {&rig.frontal, &rig.lateral};
  for (int v = 0; v < 2; ++v) {
    const ViewRenderer scene(*cams[v], {kWidth, kHeight}, seed, v);
    BoardRenderer renderer(board, *cams[v], {kWidth, kHeight});
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const cv::Mat clean = seen[static_cast<std::size_t>(v)] ? renderer.render(poses[i], scene.background())
                                                              : scene.background();
      frames.grey[static_cast<std::size_t>(v)].push_back(sensor.expose(clean, first_frame + i, v));
    }
  }
  return frames;
}

Status write_board_recording(const BoardFrames& frames, const std::filesystem::path& dir) {
  const FrameFormat format = FrameFormat::packed(PixelFormat::YUYV, kWidth, kHeight);
  auto writer = RecordingWriter::create(dir, format, kPhantomFps);
  if (!writer) return writer.error();
  for (std::size_t i = 0; i < frames.grey[0].size(); ++i)
    for (View view : kViews) {
      const FrameInfo info{i, static_cast<std::int64_t>(std::llround(double(i) * 1e9 / kPhantomFps))};
      if (auto s = writer->write(view, Frame::owning(format, info, to_yuyv(frames.grey[static_cast<int>(view)][i]))); !s)
        return s;
    }
  return writer->finish(nullptr, fmt::format("phantom calibration board, {} frames", frames.grey[0].size()));
}

}  // namespace spinewatch::phantom
