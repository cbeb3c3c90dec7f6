// The test solids' meshes as BodySets (issue 40 item 1): mass and volume
// against the exact solids and the radius the mesh contains, and the
// boundary faces the 3D detection takes (a closed surface oriented
// outward).
#include "solids_3d.h"

#include <bodies/static_newton.h>
#include <cmath>
#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace softpack;
using namespace softpack::test_solids;

TEST(Bodies3D, MassIsDensityTimesTheMeshedVolume)
{
  for (const std::string name : {"sphere", "cylinder"})
  {
    const bool sphere = name == "sphere";
    const bodies::BodySet bodies = solid(name);
    ASSERT_EQ(bodies.dim(), 3);
    ASSERT_EQ(bodies.num_bodies(), 1);
    const bodies::Body& body = bodies.body(0);
    EXPECT_EQ(body.num_dofs(), 3 * int(body.nodes.size()));
    const double V = body.reference_area;
    const std::vector<double> cells = bodies.cell_reference_area();
    // The sum of the tetrahedra against the boundary's divergence theorem
    EXPECT_NEAR(std::accumulate(cells.begin(), cells.end(), 0.0), V, 1e-13 * V);
    EXPECT_NEAR(bodies.body_current_area()[0], V, 1e-13 * V);
    // Against the analytic volume, to the mesh's own error
    const double R = D / 2, r = inner_radius(bodies, sphere);
    const double exact = sphere ? M_PI / 6 * D * D * D : M_PI * R * R * H;
    const double lower = exact * std::pow(r / R, sphere ? 3 : 2);
    EXPECT_LT(V, exact);
    EXPECT_GT(V, lower);
    EXPECT_LT((exact - V) / exact, 0.1); // the meshes are coarse: 4 mm
    RecordProperty(name + "_volume_over_exact", std::to_string(V / exact));
    RecordProperty(name + "_inscribed_over_exact",
                   std::to_string(lower / exact));
    // Lumped: rho V in each direction; consistent: the sum of one
    // direction's block is rho V
    const Eigen::VectorXd& m = bodies.lumped_mass()[0];
    const bodies::BodyMatrix& M = bodies.consistent_mass()[0];
    for (int c = 0; c < 3; ++c)
    {
      double lumped = 0;
      for (int k = c; k < m.size(); k += 3)
      {
        EXPECT_GT(m[k], 0);
        lumped += m[k];
      }
      EXPECT_NEAR(lumped, rho * V, 1e-12 * rho * V);
      Eigen::VectorXd e = Eigen::VectorXd::Zero(m.size());
      for (int k = c; k < m.size(); k += 3)
        e[k] = 1;
      EXPECT_NEAR(e.dot(bodies::symmetric_product(M, e)), rho * V,
                  1e-12 * rho * V);
    }
  }
}

/// neo_hookean_nodal (the averaged nodal pressure) is neo_hookean under a
/// homogeneous deformation (J the same at every node) and has the same
/// derivatives' checks

TEST(Bodies3D, BoundaryFacesAreAClosedSurfaceOrientedOutward)
{
  // What the 3D detection's BoundarySurface takes: every edge in exactly
  // two faces, once each way, and (b - a) x (c - a) outward (the sphere is
  // convex: away from its centre)
  const bodies::BodySet bodies = solid("sphere");
  const bodies::Body& body = bodies.body(0);
  std::span<const double> X = bodies.reference_coordinates();
  std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
  for (const auto& f : body.boundary_faces)
  {
    for (int k = 0; k < 3; ++k)
      ++edges[{f[k], f[(k + 1) % 3]}];
    double p[3][3], n[3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        p[k][c] = X[3 * body.nodes[f[k]] + c];
    for (int c = 0; c < 3; ++c)
      n[c] = (p[1][(c + 1) % 3] - p[0][(c + 1) % 3]) *
                 (p[2][(c + 2) % 3] - p[0][(c + 2) % 3]) -
             (p[1][(c + 2) % 3] - p[0][(c + 2) % 3]) *
                 (p[2][(c + 1) % 3] - p[0][(c + 1) % 3]);
    EXPECT_GT(n[0] * (p[0][0] + p[1][0] + p[2][0]) +
                  n[1] * (p[0][1] + p[1][1] + p[2][1]) +
                  n[2] * (p[0][2] + p[1][2] + p[2][2]),
              0);
  }
  for (const auto& [edge, count] : edges)
  {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
  // Euler: a sphere's surface has V - E + F = 2
  const std::size_t V = body.boundary_nodes.size(), E = edges.size() / 2,
                    F = body.boundary_faces.size();
  EXPECT_EQ(V + F, E + 2);
}
