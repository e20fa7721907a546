#include "upright_outline.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <map>

namespace spinewatch::cvsm_detail {
namespace {

// Where the ray through `pixel` meets the plane n·X = d; nothing when it
// runs along the plane or away from it.
std::optional<Eigen::Vector3d> on_plane(const CameraModel& camera, const Eigen::Vector2d& pixel,
                                        const Eigen::Vector3d& n, double d) {
  const Eigen::Vector3d o = camera.centre_in_world();
  const Eigen::Vector3d r = camera.ray_through(pixel);
  const double along = n.dot(r);
  if (std::abs(along) < 1e-9) return std::nullopt;
  const double t = (d - n.dot(o)) / along;
  if (t <= 0) return std::nullopt;
  return o + t * r;
}

// A set pixel with an unset 4-neighbour, or on the image's border.
bool on_outline(const BitMask& m, int x, int y) {
  if (x == 0 || y == 0 || x == m.width() - 1 || y == m.height() - 1) return true;
  return !m.get(x - 1, y) || !m.get(x + 1, y) || !m.get(x, y - 1) || !m.get(x, y + 1);
}

bool on_border(const BitMask& m, int x, int y) {
  return x == 0 || y == 0 || x == m.width() - 1 || y == m.height() - 1;
}

// The horizontal unit vector perpendicular to `d`'s horizontal part (the
// normal of the vertical plane containing d); zero when d is vertical.
Eigen::Vector3d horizontal_normal(const Eigen::Vector3d& d) {
  const Eigen::Vector3d n(-d.z(), 0, d.x());
  const double length = n.norm();
  return length < 1e-9 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(n / length);
}

// Where the vertical planes n₀·X = d₀ and n₁·X = d₁ (horizontal normals)
// cross, as (x, z); nothing when they are within about 6° of parallel.
std::optional<Eigen::Vector2d> crossing(const std::array<Eigen::Vector3d, 2>& n, const std::array<double, 2>& d) {
  Eigen::Matrix2d a;
  a << n[0].x(), n[0].z(), n[1].x(), n[1].z();
  if (std::abs(a.determinant()) < 0.1) return std::nullopt;
  return Eigen::Vector2d(a.inverse() * Eigen::Vector2d(d[0], d[1]));
}

// Where the two cameras' lines of sight (the rays through their principal
// points) cross, seen from above: where a station's cameras are aimed, and
// so where the subject is looked for first. The origin when they do not.
Eigen::Vector2d sight_crossing(const CameraRig& rig) {
  std::array<Eigen::Vector3d, 2> n;
  std::array<double, 2> d{};
  for (int v = 0; v < 2; ++v) {
    const CameraModel& c = v == 0 ? rig.frontal : rig.lateral;
    const Eigen::Vector3d sight = c.R.transpose() * Eigen::Vector3d::UnitZ();
    n[static_cast<std::size_t>(v)] = horizontal_normal(sight);
    d[static_cast<std::size_t>(v)] = n[static_cast<std::size_t>(v)].dot(c.centre_in_world());
  }
  return crossing(n, d).value_or(Eigen::Vector2d::Zero());
}

}  // namespace

PlaneOutline plane_outline(const CameraModel& camera, const BitMask& mask, const Eigen::Vector2d& axis) {
  PlaneOutline out;
  out.origin = {axis.x(), 0, axis.y()};
  const Eigen::Vector3d centre = camera.centre_in_world();
  // The plane faces the camera: its normal is the horizontal direction
  // from the axis to the camera.
  Eigen::Vector3d normal = centre - out.origin;
  normal.y() = 0;
  if (normal.norm() < 1e-6) return out;  // a camera straight above the axis sees no vertical plane
  normal.normalize();
  out.across = normal.cross(Eigen::Vector3d::UnitY());
  const double offset = normal.dot(out.origin);
  const double focal = camera.camera_matrix(1, 1) > 0 ? camera.camera_matrix(1, 1) : 1.0;

  double top = -std::numeric_limits<double>::infinity(), bottom = std::numeric_limits<double>::infinity();
  double border_top = -std::numeric_limits<double>::infinity();
  double pixel_mm = 0;  // the size of a pixel on the plane at the top
  // The outline's edge, not its pixels' centres: half a pixel beyond a
  // pixel, along whichever of its four sides rises most.
  constexpr std::array<std::array<double, 2>, 4> kSides{{{-0.5, 0}, {0.5, 0}, {0, -0.5}, {0, 0.5}}};
  for (int y = 0; y < mask.height(); ++y) {
    const std::uint64_t* row = mask.row(y);
    for (int w = 0; w < mask.words_per_row(); ++w) {
      for (std::uint64_t bits = row[w]; bits != 0; bits &= bits - 1) {
        const int x = w * 64 + std::countr_zero(bits);
        if (!on_outline(mask, x, y)) continue;
        const Eigen::Vector2d pixel(x, y);
        const std::optional<Eigen::Vector3d> p = on_plane(camera, pixel, normal, offset);
        if (!p) continue;
        out.points.push_back({(*p - out.origin).dot(out.across), p->y()});
        bottom = std::min(bottom, p->y());
        double edge = p->y();
        for (const auto& side : kSides)
          if (const auto q = on_plane(camera, pixel + Eigen::Vector2d(side[0], side[1]), normal, offset))
            edge = std::max(edge, q->y());
        if (edge > top) {
          top = edge;
          pixel_mm = (*p - centre).norm() / focal;
        }
        if (on_border(mask, x, y)) border_top = std::max(border_top, edge);
      }
    }
  }
  if (out.points.empty()) return out;
  out.top_y = top;
  out.bottom_y = bottom;
  // Three pixels: a head cut by the border a little beside its top still
  // reaches higher beyond it than the outline shows.
  out.top_cut = border_top >= top - 3 * pixel_mm;
  return out;
}

std::optional<Eigen::Vector3d> trunk_centre(const PlaneOutline& outline, double from, double to) {
  constexpr double kBandMm = 10;
  const double span = outline.top_y - outline.bottom_y;
  if (outline.points.empty() || span <= 0) return std::nullopt;
  const double high = outline.top_y - from * span, low = outline.top_y - to * span;
  struct Band {
    double first = std::numeric_limits<double>::infinity(), last = -std::numeric_limits<double>::infinity();
  };
  std::map<int, Band> bands;
  for (const PlaneOutline::Point& p : outline.points) {
    if (p.y > high || p.y < low) continue;
    Band& b = bands[static_cast<int>(std::floor((outline.top_y - p.y) / kBandMm))];
    b.first = std::min(b.first, p.across);
    b.last = std::max(b.last, p.across);
  }
  std::vector<double> middles;
  for (const auto& entry : bands)
    if (entry.second.last > entry.second.first) middles.push_back(0.5 * (entry.second.first + entry.second.last));
  if (middles.empty()) return std::nullopt;
  const auto mid = middles.begin() + static_cast<std::ptrdiff_t>(middles.size() / 2);
  std::nth_element(middles.begin(), mid, middles.end());
  return Eigen::Vector3d(outline.origin + *mid * outline.across + 0.5 * (high + low) * Eigen::Vector3d::UnitY());
}

Eigen::Vector2d subject_axis(const CameraRig& rig, const BitMask& frontal, const BitMask& lateral, int rounds) {
  Eigen::Vector2d axis = sight_crossing(rig);
  for (int round = 0; round < rounds; ++round) {
    std::array<Eigen::Vector3d, 2> n;
    std::array<double, 2> d{};
    for (std::size_t v = 0; v < 2; ++v) {
      const CameraModel& camera = v == 0 ? rig.frontal : rig.lateral;
      const std::optional<Eigen::Vector3d> centre = trunk_centre(plane_outline(camera, v == 0 ? frontal : lateral, axis), 0.25, 0.5);
      if (!centre) return axis;
      // The centre line and the camera span a vertical plane.
      n[v] = horizontal_normal(*centre - camera.centre_in_world());
      d[v] = n[v].dot(camera.centre_in_world());
    }
    const std::optional<Eigen::Vector2d> next = crossing(n, d);
    if (!next) return axis;
    axis = *next;
  }
  return axis;
}

}  // namespace spinewatch::cvsm_detail
