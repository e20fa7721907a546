#pragma once
// Convex solids the body and the room are built of (body.cpp, limbs.cpp).
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "spinewatch/estimator/units.hpp"
#include "spinewatch/phantom/body.hpp"

namespace spinewatch::phantom::detail {

// Points on a unit sphere, enough that the hull of their projection is
// within a fraction of a pixel of the true outline at this image scale.
const std::vector<Eigen::Vector3d>& unit_sphere();

// Two spheres and the hull between them.
Solid capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra, double rb, std::uint8_t shade);

// A box: its centre, its axes (columns) and half-extents along them.
Solid box(const Eigen::Vector3d& centre, const Eigen::Matrix3d& axes, const Eigen::Vector3d& half, std::uint8_t shade);

}  // namespace spinewatch::phantom::detail
