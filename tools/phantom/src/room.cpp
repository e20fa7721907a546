#include "spinewatch/phantom/room.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "backdrop_wall.hpp"
#include "spinewatch/estimator/units.hpp"

namespace spinewatch::phantom {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Sample {
  float luma;
  cv::Vec2f chroma;
};

// A small integer hash: the same texture for the same cell, whatever the order.
float cell_noise(std::int64_t a, std::int64_t b, std::uint32_t salt) {
  std::uint64_t h = std::uint64_t(a) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(b) * 0xC2B2AE3D27D4EB4Full ^ salt;
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return float(h & 0xFFFF) / 65535.0f;  // [0, 1]
}

// The horizontal frame of one view: `forward` from the camera across the
// subject's axis towards the wall, `side` to the image's right-ish.
struct ViewFrame {
  Eigen::Vector3d forward, side;
  Eigen::Vector3d at(double behind, double across, double up) const {
    return behind * forward + across * side + up * Eigen::Vector3d::UnitY();
  }
};

ViewFrame view_frame(const CameraModel& camera) {
  Eigen::Vector3d axis = camera.R.transpose() * Eigen::Vector3d::UnitZ();
  axis.y() = 0;
  axis.normalize();
  return {axis, Eigen::Vector3d::UnitY().cross(axis)};
}

enum class Surface : std::uint8_t { Plain, Bookcase, Poster };
struct ClutterBox {
  SceneBox box;
  Surface surface = Surface::Plain;
  std::uint32_t salt = 0;
};
struct Poster {
  double across0, across1, up0, up1;
  int pattern;
  std::uint32_t salt;
  cv::Vec2f chroma;
};

class ClutteredRoom {
 public:
  ClutteredRoom(const CameraModel& camera, std::uint32_t seed, int view_index) : frame_(view_frame(camera)) {
    std::seed_seq seq{seed, 7u, std::uint32_t(view_index)};
    std::mt19937 rng(seq);
    std::uniform_real_distribution<double> u(0, 1);
    const auto chroma = [&] { return cv::Vec2f(float(50 * u(rng) - 25), float(50 * u(rng) - 25)); };
    const Eigen::Vector3d camera_centre = camera.centre_in_world();
    wall_ = kWallBehindMm;
    camera_behind_ = camera_centre.dot(frame_.forward);  // negative: the camera is in front
    // Two bookcases against the wall, one each side of the subject.
    for (double sign : {-1.0, 1.0}) {
      const double width = 800 + 250 * u(rng), height = 1800 + 300 * u(rng);
      const double across = sign * (750 + 900 * u(rng));
      add({frame_.at(wall_ - 170, across, height / 2), Eigen::Matrix3d::Identity(), {170, height / 2, width / 2}, float(70 + 50 * u(rng)), chroma()},
          Surface::Bookcase, std::uint32_t(rng()));
    }
    // A cabinet, and boxes on the floor, one of them behind the subject.
    {
      const double across = (u(rng) < 0.5 ? -1 : 1) * (500 + 1200 * u(rng));
      add({frame_.at(700 + 500 * u(rng), across, 450), Eigen::Matrix3d::Identity(), {250, 450, 300}, float(90 + 100 * u(rng)), chroma()},
          Surface::Plain, std::uint32_t(rng()));
    }
    for (int k = 0; k < 3; ++k) {
      const double size = 150 + 200 * u(rng);
      const double across = k == 0 ? 400 * (u(rng) - 0.5) : (u(rng) < 0.5 ? -1 : 1) * (600 + 1400 * u(rng));
      const double behind = k == 0 ? 800 + 400 * u(rng) : 400 + 900 * u(rng);
      add({frame_.at(behind, across, size), Eigen::Matrix3d::Identity(), {size, size, size * (0.8 + 0.6 * u(rng))}, float(40 + 180 * u(rng)), chroma()},
          Surface::Plain, std::uint32_t(rng()));
    }
    for (int k = 0; k < 4; ++k) {
      const double w = 350 + 500 * u(rng), h = 300 + 450 * u(rng);
      const double across = (u(rng) - 0.5) * 3600, up = 1000 + 1000 * u(rng);
      posters_.push_back({across - w / 2, across + w / 2, up - h / 2, up + h / 2, int(rng() % 3), std::uint32_t(rng()), chroma()});
    }
    rug_ = {-900 + 600 * u(rng), 700 + 600 * u(rng), 200 + 300 * u(rng), 1100 + 300 * u(rng), 0, std::uint32_t(rng()), chroma()};
  }

  Sample sample(const Eigen::Vector3d& origin, const Eigen::Vector3d& d) const {
    double best = kInf;
    const ClutterBox* hit_box = nullptr;
    for (const ClutterBox& b : boxes_)
      if (const double t = b.box.hit(origin, d); t < best) {
        best = t;
        hit_box = &b;
      }
    const double along = d.dot(frame_.forward);
    const double t_wall = along > 1e-6 ? (wall_ - camera_behind_) / along : kInf;
    const double t_floor = d.y() < 0 ? -origin.y() / d.y() : kInf;
    if (hit_box && best < t_wall && best < t_floor) return box_surface(*hit_box, origin + best * d);
    if (t_floor < t_wall) return floor_surface(origin + t_floor * d);
    if (t_wall < kInf) return wall_surface(origin + t_wall * d);
    return {170, {0, 0}};
  }

 private:
  void add(SceneBox box, Surface surface, std::uint32_t salt) {
    box.axes.col(0) = frame_.forward;
    box.axes.col(1) = Eigen::Vector3d::UnitY();
    box.axes.col(2) = frame_.side;
    boxes_.push_back({box, surface, salt});
  }

  Sample box_surface(const ClutterBox& b, const Eigen::Vector3d& p) const {
    const Eigen::Vector3d local = b.box.axes.transpose() * (p - b.box.centre);
    // Lit from above: tops lighter, the faces towards the camera as shaded.
    const bool top = local.y() > b.box.half.y() - 1;
    float luma = b.box.shade * (top ? 1.15f : 1.0f);
    cv::Vec2f chroma = b.box.chroma;
    if (b.surface == Surface::Bookcase && !top) {
      // Boards every 380 mm; books of random width, height and colour between.
      const double y = local.y() + b.box.half.y();
      const auto shelf = std::int64_t(std::floor(y / 380));
      const double in_shelf = y - double(shelf) * 380;
      const auto book = std::int64_t(std::floor((local.z() + b.box.half.z()) / 38));
      const float r = cell_noise(shelf, book, b.salt);
      const double book_height = 200 + 150 * cell_noise(book, shelf, b.salt + 1);
      if (in_shelf < 25) luma = 200;
      else if (in_shelf < 25 + book_height && r > 0.12f) {
        luma = 30 + 200 * r;
        chroma = cv::Vec2f(60 * cell_noise(shelf, book, b.salt + 2) - 30, 60 * cell_noise(shelf, book, b.salt + 3) - 30);
      } else luma = 0.5f * b.box.shade;  // the dark back of the shelf
    }
    luma += 12 * (cell_noise(std::int64_t(p.x() / 7), std::int64_t(p.y() / 7 + p.z() / 7), b.salt) - 0.5f);
    return {luma, chroma};
  }

  Sample floor_surface(const Eigen::Vector3d& p) const {
    const double behind = p.dot(frame_.forward), across = p.dot(frame_.side);
    if (across > rug_.across0 && across < rug_.across1 && behind > rug_.up0 && behind < rug_.up1) {
      const double stripe = std::sin((across - rug_.across0) / 45.0) * std::sin((behind - rug_.up0) / 70.0);
      return {float(120 + 60 * stripe), rug_.chroma};
    }
    const auto tx = std::int64_t(std::floor(p.x() / 500)), tz = std::int64_t(std::floor(p.z() / 500));
    const bool grout = std::fmod(p.x() - 500.0 * double(tx), 500.0) < 12 || std::fmod(p.z() - 500.0 * double(tz), 500.0) < 12;
    const float tile = 135 + 30 * cell_noise(tx, tz, 11);
    return {grout ? 80.0f : tile + 8 * (cell_noise(std::int64_t(p.x() / 9), std::int64_t(p.z() / 9), 12) - 0.5f),
            cv::Vec2f(-3, 5)};
  }

  Sample wall_surface(const Eigen::Vector3d& p) const {
    const double across = p.dot(frame_.side), up = p.y();
    for (const Poster& poster : posters_) {
      if (across < poster.across0 || across > poster.across1 || up < poster.up0 || up > poster.up1) continue;
      const double x = across - poster.across0, y = up - poster.up0;
      if (x < 20 || y < 20 || poster.across1 - across < 20 || poster.up1 - up < 20) return {35, {0, 0}};  // the frame
      float luma = 0;
      switch (poster.pattern) {
        case 0:  // blocks of colour
          luma = 40 + 190 * cell_noise(std::int64_t(x / 90), std::int64_t(y / 70), poster.salt);
          break;
        case 1:  // diagonal stripes
          luma = float(135 + 95 * std::sin((x + y) / 25.0));
          break;
        default:  // a disc on a plain ground
          luma = std::hypot(x - 0.5 * (poster.across1 - poster.across0), y - 0.5 * (poster.up1 - poster.up0)) < 110 ? 225
                                                                                                                 : 60;
      }
      return {luma, poster.chroma};
    }
    return {float(175 + 10 * (up / 1000.0 - 1.0) + 10 * cell_noise(std::int64_t(across / 300), std::int64_t(up / 300), 5)),
            cv::Vec2f(-8, 10)};
  }

  ViewFrame frame_;
  double wall_ = 0, camera_behind_ = 0;
  std::vector<ClutterBox> boxes_;
  std::vector<Poster> posters_;
  Poster rug_{};
};

// Supersampled 2 × 2: the depth edges and the patterns antialiased.
void paint_cluttered(const CameraModel& camera, std::uint32_t seed, int view_index, cv::Mat& luma, cv::Mat& chroma) {
  const ClutteredRoom room(camera, seed, view_index);
  const Eigen::Vector3d origin = camera.centre_in_world();
  for (int v = 0; v < luma.rows; ++v)
    for (int u = 0; u < luma.cols; ++u) {
      float y = 0;
      cv::Vec2f c(0, 0);
      for (double dv : {0.25, 0.75})
        for (double du : {0.25, 0.75}) {
          const Sample s = room.sample(origin, camera.ray_through({u + du, v + dv}));
          y += 0.25f * s.luma;
          c += 0.25f * s.chroma;
        }
      luma.at<float>(v, u) = y;
      chroma.at<cv::Vec2f>(v, u) = c;
    }
}

// Boxes placed in the subject's frame turned with the subject about the
// vertical through the origin.
void turn_with_subject(std::vector<SceneBox>& boxes, double heading_deg) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(heading_deg * kRadPerDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (SceneBox& b : boxes) {
    b.centre = turn * b.centre;
    b.axes = turn;
  }
}

// The photograph scaled to cover the view and cropped to its middle.
void paint_backdrop(const cv::Mat& photo, cv::Mat& luma, cv::Mat& chroma) {
  const double scale = std::max(double(luma.cols) / photo.cols, double(luma.rows) / photo.rows);
  cv::Mat scaled;
  cv::resize(photo, scaled, cv::Size(), scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  const cv::Rect crop((scaled.cols - luma.cols) / 2, (scaled.rows - luma.rows) / 2, luma.cols, luma.rows);
  cv::Mat ycrcb;
  cv::cvtColor(scaled(crop), ycrcb, cv::COLOR_BGR2YCrCb);  // BT.601, as a YUYV camera delivers
  for (int v = 0; v < luma.rows; ++v)
    for (int u = 0; u < luma.cols; ++u) {
      const cv::Vec3b p = ycrcb.at<cv::Vec3b>(v, u);
      luma.at<float>(v, u) = p[0];
      chroma.at<cv::Vec2f>(v, u) = cv::Vec2f(float(p[2]) - 128, float(p[1]) - 128);
    }
}

}  // namespace

double SceneBox::hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  const Eigen::Vector3d o = axes.transpose() * (origin - centre), d = axes.transpose() * direction;
  double near = 0, far = kInf;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (std::abs(o[k]) > half[k]) return kInf;
      continue;
    }
    double t0 = (-half[k] - o[k]) / d[k], t1 = (half[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
    if (near > far) return kInf;
  }
  return near > 0 ? near : kInf;
}

std::vector<SceneBox> furniture_boxes(Furniture furniture, double heading_deg) {
  // In the subject's frame (X forwards), then turned with the subject.
  std::vector<SceneBox> boxes;
  const cv::Vec2f wood(-14, 16), panel(-8, 10);
  switch (furniture) {
    case Furniture::None:
      break;
    case Furniture::Desk:
      boxes.push_back({{625, 705, 0}, Eigen::Matrix3d::Identity(), {375, 15, 700}, 175, wood});   // the top
      boxes.push_back({{975, 400, 0}, Eigen::Matrix3d::Identity(), {15, 290, 690}, 120, panel});  // the front panel
      for (double side : {-1.0, 1.0}) boxes.push_back({{625, 352, side * 685}, Eigen::Matrix3d::Identity(), {375, 338, 15}, 130, panel});
      break;
    case Furniture::Bench:
      boxes.push_back({{650, 880, 0}, Eigen::Matrix3d::Identity(), {300, 20, 600}, 170, wood});
      boxes.push_back({{930, 480, 0}, Eigen::Matrix3d::Identity(), {20, 380, 590}, 115, panel});
      for (double side : {-1.0, 1.0}) boxes.push_back({{370, 430, side * 570}, Eigen::Matrix3d::Identity(), {20, 430, 20}, 110, panel});
      break;
  }
  turn_with_subject(boxes, heading_deg);
  return boxes;
}

std::vector<SceneBox> chair_boxes(Chair chair, const ChairPlace& place, double heading_deg) {
  if (chair == Chair::None) return {};
  // Grey levels: the black chair's fabric and frame 30 and 25 (the
  // trousers are 48–60), the grey one's 120 and 110.
  const float fabric_shade = chair == Chair::Black ? 30 : 120, frame_shade = chair == Chair::Black ? 25 : 110;
  const cv::Vec2f fabric(4, -2), frame(0, 0);
  const double seat_half_depth = 0.5 * (place.seat_front_x - place.seat_back_x);
  const double seat_mid_x = place.seat_back_x + seat_half_depth;
  const double seat_thickness = 50, leg_half = 15, back_thickness = 30, back_height = 420;
  std::vector<SceneBox> boxes;
  boxes.push_back({{seat_mid_x, place.seat_top_y - 0.5 * seat_thickness, 0}, Eigen::Matrix3d::Identity(),
                   {seat_half_depth, 0.5 * seat_thickness, place.seat_half_width}, fabric_shade, fabric});
  const double leg_top = place.seat_top_y - seat_thickness;
  for (double x : {place.seat_back_x + 2 * leg_half, place.seat_front_x - 2 * leg_half})
    for (double side : {-1.0, 1.0})
      boxes.push_back({{x, 0.5 * leg_top, side * (place.seat_half_width - 2 * leg_half)}, Eigen::Matrix3d::Identity(),
                       {leg_half, 0.5 * leg_top, leg_half}, frame_shade, frame});
  boxes.push_back({{place.seat_back_x - 0.5 * back_thickness, place.seat_top_y + 0.5 * back_height, 0},
                   Eigen::Matrix3d::Identity(),
                   {0.5 * back_thickness, 0.5 * back_height, place.seat_half_width - 20}, fabric_shade, fabric});
  turn_with_subject(boxes, heading_deg);
  return boxes;
}

cv::Mat paint_room(const RoomSetup& room, const CameraModel& camera, std::uint32_t seed, int view_index, cv::Mat& luma,
                   cv::Mat& chroma) {
  if (!room.backdrop.empty()) paint_backdrop(room.backdrop, luma, chroma);
  else if (room.kind == RoomKind::Cluttered) paint_cluttered(camera, seed, view_index, luma, chroma);
  cv::Mat depth(luma.size(), CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  if (room.furniture.empty()) return depth;
  std::seed_seq seq{seed, 9u, std::uint32_t(view_index)};
  std::mt19937 rng(seq);
  std::uniform_real_distribution<float> grain(-6.f, 6.f);
  const Eigen::Vector3d origin = camera.centre_in_world();
  for (int v = 0; v < luma.rows; ++v)
    for (int u = 0; u < luma.cols; ++u) {
      const Eigen::Vector3d d = camera.ray_through({u + 0.5, v + 0.5});
      double best = kInf;
      const SceneBox* nearest = nullptr;
      for (const SceneBox& b : room.furniture)
        if (const double t = b.hit(origin, d); t < best) {
          best = t;
          nearest = &b;
        }
      const float g = grain(rng);
      if (!nearest) continue;
      depth.at<float>(v, u) = float(camera.to_camera(origin + best * d).z());
      luma.at<float>(v, u) = nearest->shade + g;
      chroma.at<cv::Vec2f>(v, u) = nearest->chroma;
    }
  return depth;
}

}  // namespace spinewatch::phantom
