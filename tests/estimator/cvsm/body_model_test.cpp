// The body model's control points against the textbook construction: each
// plane's ring of kControlPoints points at k · 30°, an ellipse with its
// front and back half-depths and its half-width, about the ring's centre.
// build_body_model takes each angle's cos and sin from a table and adds by
// component; the points must be the same numbers, to the bit.
#include <gtest/gtest.h>

#include <cmath>

#include "spinewatch/estimator/anatomy/spine_spec.hpp"
#include "spinewatch/estimator/cvsm/body_model.hpp"

namespace spinewatch {
namespace {

Eigen::Vector3d reference_point(const ControlPlane& p, int k) {
  const double a = k * (2.0 * M_PI / kControlPoints);
  const double c = std::cos(a), s = std::sin(a);
  const double radial = c * (c > 0 ? p.front : p.back);
  const Eigen::Vector3d local =
      p.axis_x ? Eigen::Vector3d(0, radial, s * p.half_width) : Eigen::Vector3d(radial, 0, s * p.half_width);
  return p.offset + local;
}

TEST(BodyModel, ControlPointsAreTheRingsOfTheReferenceToTheBit) {
  for (const SubjectPosture posture : {SubjectPosture::Standing, SubjectPosture::Seated})
    for (const double height : {1480.0, 1620.0, 1910.0}) {
      BodyShape shape;
      shape.height_mm = height;
      shape.width_scale = 0.9;
      shape.posture = posture;
      const BodyModel m = build_body_model(generic_cvsm_spec(), generic_spine_spec(), shape,
                                           {10, generic_spine_spec().l5_height_fraction * height, 0});
      ASSERT_EQ(m.local_points.size(), m.planes.size() * kControlPoints);
      for (std::size_t p = 0; p < m.planes.size(); ++p)
        for (int k = 0; k < kControlPoints; ++k) {
          const Eigen::Vector3d expected = reference_point(m.planes[p], k);
          const Eigen::Vector3d& got = m.local_points[p * kControlPoints + static_cast<std::size_t>(k)];
          for (int i = 0; i < 3; ++i)
            EXPECT_EQ(got[i], expected[i]) << "plane " << p << ", point " << k << ", axis " << i;
        }
    }
}

}  // namespace
}  // namespace spinewatch
