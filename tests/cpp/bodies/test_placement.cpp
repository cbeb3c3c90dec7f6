// Each body's centroid and rotation (bodies/placement.h) against a rigid
// motion, where both are known exactly, and a stretch, which rotates
// nothing.
#include "mesh_fixtures.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <bodies/placement.h>
#include <cmath>
#include <gtest/gtest.h>
#include <material_registry.h>

using namespace softpack;

namespace
{
/// A disk centred at (0.01, 0.02) and a rectangle [0.03, 0.05] x [-0.01,
/// 0.005]: centroids known.
bodies::BodySet two_bodies()
{
  return bodies::BodySet(
      test::bodies_mesh({test::disk(0.01, 0.02, 0.01, 4),
                         test::rectangle(0.03, -0.01, 0.02, 0.015, 4, 3)}),
      forms::find_material("neo_hookean"),
      bodies::plane_strain_parameters(0.15e6), 1180);
}

/// x = c_b + t_b + A_b (X - c_b) on body b, c_b its reference centroid
void move(bodies::BodySet& set, const double centre[2][2],
          const double shift[2][2], const double A[2][4])
{
  std::span<double> u = set.displacement();
  std::span<const double> X = set.reference_coordinates();
  for (int b = 0; b < set.num_bodies(); ++b)
    for (std::int32_t n : set.body(b).nodes)
    {
      const double dx = X[2 * n] - centre[b][0],
                   dy = X[2 * n + 1] - centre[b][1];
      const double x = centre[b][0] + shift[b][0] + A[b][0] * dx + A[b][1] * dy;
      const double y = centre[b][1] + shift[b][1] + A[b][2] * dx + A[b][3] * dy;
      u[2 * n] = x - X[2 * n];
      u[2 * n + 1] = y - X[2 * n + 1];
    }
}
} // namespace

TEST(Placement, ARigidMotionGivesItsTranslationAndAngle)
{
  bodies::BodySet set = two_bodies();
  // The disk's polygon is symmetric about its centre: its centroid is the
  // centre; the rectangle's is its middle.
  const double centre[2][2] = {{0.01, 0.02}, {0.04, -0.0025}};
  const std::vector<bodies::Placement> rest = bodies::placements(set);
  for (int b = 0; b < 2; ++b)
  {
    EXPECT_NEAR(rest[b].x, centre[b][0], 1e-15);
    EXPECT_NEAR(rest[b].y, centre[b][1], 1e-15);
    EXPECT_EQ(rest[b].rotation, 0.0);
  }
  const double angle[2] = {0.3, -2.9}; // the second past -pi / 2
  const double shift[2][2] = {{0.004, -0.002}, {-0.001, 0.003}};
  double A[2][4];
  for (int b = 0; b < 2; ++b)
  {
    const double c = std::cos(angle[b]), s = std::sin(angle[b]);
    A[b][0] = c, A[b][1] = -s, A[b][2] = s, A[b][3] = c;
  }
  move(set, centre, shift, A);
  const std::vector<bodies::Placement> moved = bodies::placements(set);
  for (int b = 0; b < 2; ++b)
  {
    EXPECT_NEAR(moved[b].x, centre[b][0] + shift[b][0], 1e-15);
    EXPECT_NEAR(moved[b].y, centre[b][1] + shift[b][1], 1e-15);
    EXPECT_NEAR(moved[b].rotation, angle[b], 1e-13);
  }
}

TEST(Placement, AStretchAlongItsAxesRotatesNothing)
{
  bodies::BodySet set = two_bodies();
  const double centre[2][2] = {{0.01, 0.02}, {0.04, -0.0025}};
  const double shift[2][2] = {{0, 0}, {0, 0}};
  const double A[2][4] = {{1.2, 0, 0, 0.9}, {0.8, 0, 0, 1.1}};
  move(set, centre, shift, A);
  for (const bodies::Placement& p : bodies::placements(set))
    EXPECT_NEAR(p.rotation, 0.0, 1e-15);
}
