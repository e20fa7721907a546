#pragma once
// The parameter vectors the tracker's searches move (coordinate_search.hpp):
// the trunk's pose and the articulated limbs' angles, each as a flat array
// of numbers, and the way to and from the model's own poses.
#include <array>
#include <cstddef>

#include "spinewatch/estimator/cvsm/body_model.hpp"

namespace spinewatch::cvsm_detail {

// The search's parameters: total trunk flexion T (spine and pelvis
// together, a third of it in the pelvis as in a natural forward bend),
// lateral, twist, the pelvis's share beyond that third, pelvis lateral and
// the translation. A bend then moves along one parameter instead of two,
// and the residual only settles how it is shared.
using PoseParams = std::array<double, 8>;  // T, lateral, twist, pelvis residual, pelvis lateral, tx, ty, tz
inline constexpr double kPelvisShare = 1.0 / 3.0;

PoseParams to_params(const CvsmPose& p);
// The pose with these trunk parameters and `limbs` (the heading left at 0).
CvsmPose to_pose(const PoseParams& a, const LimbPose& limbs);

// The limbs' search parameters, in degrees: per side (left, right) the
// shoulder's flexion and abduction and the elbow, the hip's flexion and
// abduction and the knee; then the head's flexion, lateral tilt and turn.
inline constexpr std::size_t kLimbParams = 15;
using LimbParams = std::array<double, kLimbParams>;

LimbParams to_limb_params(const LimbPose& l);
LimbPose to_limbs(const LimbParams& a);

// Where each angle may go from the model's neutral limbs (arms hanging,
// elbows a little flexed; legs hanging or seated), degrees: the joints'
// active ranges, so the search cannot fold a limb through the body.
inline constexpr std::array<std::array<double, 2>, kLimbParams> kLimbRange{{
    {-60, 180}, {-20, 170}, {-20, 140}, {-30, 120}, {-20, 60}, {-5, 140},  // left
    {-60, 180}, {-20, 170}, {-20, 140}, {-30, 120}, {-20, 60}, {-5, 140},  // right
    {-40, 45}, {-30, 30}, {-80, 80}}};                                      // head
bool in_range(const LimbParams& a);

}  // namespace spinewatch::cvsm_detail
