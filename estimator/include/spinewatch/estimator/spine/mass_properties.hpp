#pragma once
// A vertebra as a rigid body of particles (the paper's Eqs. 1–9): parametric
// solids voxelised into equal-mass particles, and the mass, centre of mass
// and inertia tensor those particles give.
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace spinewatch {

// An elliptic cylinder whose axis is the local Y axis.
struct EllipticCylinder {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double semi_x = 0, semi_z = 0, half_height = 0;  // mm
};

// A box with its own axes (columns of `axes`, orthonormal).
struct OrientedBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // mm
};

// A union of primitives, in mm.
struct Solid {
  std::vector<EllipticCylinder> cylinders;
  std::vector<OrientedBox> boxes;

  bool contains(const Eigen::Vector3d& p) const;
  Eigen::AlignedBox3d bounds() const;
};

// Centres of the voxels of a regular grid (spacing voxel_mm, cells centred on
// multiples of voxel_mm) that lie inside the solid, in x, then y, then z
// order. Each primitive is tested only on the voxels of its own bounds: a
// vertebra's union box is mostly empty (the processes reach far from the
// body), so testing every voxel against every primitive cost ten times
// the work, and under the sanitizers most of building a subject's spine.
std::vector<Eigen::Vector3d> voxelise(const Solid& solid, double voxel_mm);
// Every voxel of the union's bounds against every primitive: what
// voxelise() is tested against (the same points, in the same order).
std::vector<Eigen::Vector3d> voxelise_reference(const Solid& solid, double voxel_mm);

struct MassProperties {
  double mass_kg = 0;                                           // Eq. 1
  Eigen::Vector3d com_mm = Eigen::Vector3d::Zero();             // Eq. 2
  Eigen::Matrix3d inertia_kg_mm2 = Eigen::Matrix3d::Zero();     // Eqs. 3–9, about com_mm
};

// Eqs. 1–9 over equal particles of `particle_mass_kg`. When `voxel_mm` > 0
// each particle is a cube of that edge and adds its own m·v²/6 to the
// diagonal (exact for voxelised boxes; 0 gives the paper's point masses).
MassProperties mass_properties(std::span<const Eigen::Vector3d> particles_mm, double particle_mass_kg,
                               double voxel_mm = 0);

}  // namespace spinewatch
