#include "spinewatch/estimator/spine/mass_properties.hpp"

#include <cmath>

namespace spinewatch {

bool Solid::contains(const Eigen::Vector3d& p) const {
  for (const auto& c : cylinders) {
    const Eigen::Vector3d d = p - c.centre;
    if (std::abs(d.y()) <= c.half_height &&
        (d.x() * d.x()) / (c.semi_x * c.semi_x) + (d.z() * d.z()) / (c.semi_z * c.semi_z) <= 1.0)
      return true;
  }
  for (const auto& b : boxes) {
    const Eigen::Vector3d d = b.axes.transpose() * (p - b.centre);
    if ((d.cwiseAbs() - b.half_extents).maxCoeff() <= 0) return true;
  }
  return false;
}

Eigen::AlignedBox3d Solid::bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& c : cylinders) {
    const Eigen::Vector3d h(c.semi_x, c.half_height, c.semi_z);
    box.extend(c.centre - h);
    box.extend(c.centre + h);
  }
  for (const auto& b : boxes) {
    const Eigen::Vector3d h = b.axes.cwiseAbs() * b.half_extents;
    box.extend(b.centre - h);
    box.extend(b.centre + h);
  }
  return box;
}

std::vector<Eigen::Vector3d> voxelise(const Solid& solid, double voxel_mm) {
  std::vector<Eigen::Vector3d> out;
  const Eigen::AlignedBox3d box = solid.bounds();
  if (box.isEmpty() || !(voxel_mm > 0)) return out;
  const Eigen::Vector3d lo = (box.min() / voxel_mm).array().floor();
  const Eigen::Vector3d hi = (box.max() / voxel_mm).array().ceil();
  for (double x = lo.x(); x <= hi.x(); ++x)
    for (double y = lo.y(); y <= hi.y(); ++y)
      for (double z = lo.z(); z <= hi.z(); ++z) {
        const Eigen::Vector3d p = Eigen::Vector3d(x, y, z) * voxel_mm;
        if (solid.contains(p)) out.push_back(p);
      }
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
