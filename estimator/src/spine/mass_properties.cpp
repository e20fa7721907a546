#include "spinewatch/estimator/spine/mass_properties.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace spinewatch {

namespace {

// One test per primitive, shared by contains() and voxelise() so that both
// decide every point alike, to the last bit.
// A cylinder's test is two tests of separate components of d = p − centre:
// along its axis (y), and across it (x, z).
bool within_height(const EllipticCylinder& c, const Eigen::Vector3d& d) { return std::abs(d.y()) <= c.half_height; }
bool within_section(const EllipticCylinder& c, const Eigen::Vector3d& d) {
  return (d.x() * d.x()) / (c.semi_x * c.semi_x) + (d.z() * d.z()) / (c.semi_z * c.semi_z) <= 1.0;
}
bool inside(const EllipticCylinder& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - c.centre;
  return within_height(c, d) && within_section(c, d);
}
bool inside(const OrientedBox& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = b.axes.transpose() * (p - b.centre);
  return (d.cwiseAbs() - b.half_extents).maxCoeff() <= 0;
}
Eigen::AlignedBox3d bounds_of(const EllipticCylinder& c) {
  const Eigen::Vector3d h(c.semi_x, c.half_height, c.semi_z);
  return {c.centre - h, c.centre + h};
}
Eigen::AlignedBox3d bounds_of(const OrientedBox& b) {
  const Eigen::Vector3d h = b.axes.cwiseAbs() * b.half_extents;
  return {b.centre - h, b.centre + h};
}

// The grid over a solid's bounds: cell (i, j, k) is centred on
// (first + (i, j, k)) · voxel_mm.
struct VoxelGrid {
  Eigen::Vector3d first, last;  // in cells (whole numbers)
  double voxel_mm;
  Eigen::Array3i size() const { return (last - first).cast<int>().array() + 1; }
  Eigen::Vector3d centre(int i, int j, int k) const {
    // As the reference counts: first + i is exact in a double.
    return Eigen::Vector3d(first.x() + i, first.y() + j, first.z() + k) * voxel_mm;
  }
};
std::optional<VoxelGrid> grid_over(const Solid& solid, double voxel_mm) {
  const Eigen::AlignedBox3d box = solid.bounds();
  if (box.isEmpty() || !(voxel_mm > 0)) return std::nullopt;
  return VoxelGrid{(box.min() / voxel_mm).array().floor(), (box.max() / voxel_mm).array().ceil(), voxel_mm};
}

}  // namespace

bool Solid::contains(const Eigen::Vector3d& p) const {
  for (const auto& c : cylinders)
    if (inside(c, p)) return true;
  for (const auto& b : boxes)
    if (inside(b, p)) return true;
  return false;
}

Eigen::AlignedBox3d Solid::bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& c : cylinders) box.extend(bounds_of(c));
  for (const auto& b : boxes) box.extend(bounds_of(b));
  return box;
}

std::vector<Eigen::Vector3d> voxelise(const Solid& solid, double voxel_mm) {
  std::vector<Eigen::Vector3d> out;
  const auto grid = grid_over(solid, voxel_mm);
  if (!grid) return out;
  const Eigen::Array3i n = grid->size();
  std::vector<std::uint8_t> in(static_cast<std::size_t>(n.prod()), 0);
  const auto at = [&](int i, int j, int k) { return (static_cast<std::size_t>(i) * n.y() + j) * n.z() + k; };
  std::size_t inside_count = 0;
  const auto set = [&](int i, int j, int k) {
    if (!in[at(i, j, k)]) {
      in[at(i, j, k)] = 1;
      ++inside_count;
    }
  };
  // The primitive's cells, one more on each side (a point on its bounds
  // counts as inside), within the grid.
  const auto cells_of = [&](const auto& primitive) {
    const Eigen::AlignedBox3d b = bounds_of(primitive);
    const Eigen::Array3i lo = ((b.min() / voxel_mm).array().floor() - grid->first.array()).cast<int>() - 1;
    const Eigen::Array3i hi = ((b.max() / voxel_mm).array().ceil() - grid->first.array()).cast<int>() + 1;
    return std::pair<Eigen::Array3i, Eigen::Array3i>(lo.max(0), hi.min(n - 1));
  };
  // A cylinder's two tests once per row along y and once per column
  // across it, instead of once per cell: each component of d is the same
  // double whichever cell it is computed for (Eigen works per component,
  // no contraction: -ffp-contract=off), so each cell's decision is
  // inside()'s to the last bit (MassProperties.VoxeliseGivesTheReferencesPointsInItsOrder).
  for (const auto& c : solid.cylinders) {
    const auto [from, to] = cells_of(c);
    std::vector<int> rows;
    for (int j = from.y(); j <= to.y(); ++j)
      if (within_height(c, grid->centre(from.x(), j, from.z()) - c.centre)) rows.push_back(j);
    for (int i = from.x(); i <= to.x(); ++i)
      for (int k = from.z(); k <= to.z(); ++k)
        if (within_section(c, grid->centre(i, from.y(), k) - c.centre))
          for (int j : rows) set(i, j, k);
  }
  for (const auto& b : solid.boxes) {
    const auto [from, to] = cells_of(b);
    for (int i = from.x(); i <= to.x(); ++i)
      for (int j = from.y(); j <= to.y(); ++j)
        for (int k = from.z(); k <= to.z(); ++k)
          if (!in[at(i, j, k)] && inside(b, grid->centre(i, j, k))) set(i, j, k);
  }
  out.reserve(inside_count);
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k)
        if (in[at(i, j, k)]) out.push_back(grid->centre(i, j, k));
  return out;
}

std::vector<Eigen::Vector3d> voxelise_reference(const Solid& solid, double voxel_mm) {
  std::vector<Eigen::Vector3d> out;
  const auto grid = grid_over(solid, voxel_mm);
  if (!grid) return out;
  const Eigen::Array3i n = grid->size();
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k)
        if (solid.contains(grid->centre(i, j, k))) out.push_back(grid->centre(i, j, k));
  return out;
}

MassProperties mass_properties(std::span<const Eigen::Vector3d> particles, double m, double voxel_mm) {
  MassProperties out;
  if (particles.empty()) return out;
  out.mass_kg = m * double(particles.size());  // Eq. 1
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : particles) sum += m * p;
  out.com_mm = sum / out.mass_kg;  // Eq. 2
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  for (const auto& p : particles) {
    const Eigen::Vector3d r = p - out.com_mm;  // x̄, ȳ, z̄ of Eqs. 4–9
    xx += m * (r.y() * r.y() + r.z() * r.z());  // Eq. 4
    yy += m * (r.z() * r.z() + r.x() * r.x());  // Eq. 5
    zz += m * (r.x() * r.x() + r.y() * r.y());  // Eq. 6
    xy += m * r.x() * r.y();                    // Eq. 7
    xz += m * r.x() * r.z();                    // Eq. 8
    yz += m * r.y() * r.z();                    // Eq. 9
  }
  // A voxel is a cube, not a point: its own inertia about its centre.
  const double self = out.mass_kg * voxel_mm * voxel_mm / 6.0;
  out.inertia_kg_mm2 << xx + self, -xy, -xz,  //
      -xy, yy + self, -yz,                    // Eq. 3
      -xz, -yz, zz + self;
  return out;
}

}  // namespace spinewatch
