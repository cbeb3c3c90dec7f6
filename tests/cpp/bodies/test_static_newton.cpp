// A single disk under a pinching load, solved by the static Newton method:
// the convergence must be quadratic (checked on the residual history).
#include "mesh_fixtures.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <bodies/static_newton.h>
#include <cmath>
#include <gtest/gtest.h>
#include <material_registry.h>

using namespace softpack;

TEST(StaticNewton, PinchedDiskConvergesQuadratically)
{
  constexpr double mu = 0.15e6, R = 0.01;
  bodies::BodySet bodies(test::bodies_mesh({test::disk(0, 0, R, 8)}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), 1180);
  std::span<const double> X = bodies.reference_coordinates();
  const bodies::Body& body = bodies.body(0);

  // Self-equilibrated load: boundary nodes within 30 degrees of the top are
  // pushed down, those near the bottom pushed up; total P = 0.15 mu D.
  std::vector<double> f_ext(bodies.num_dofs(), 0.0);
  std::vector<std::int32_t> top, bottom;
  for (std::int32_t local : body.boundary_nodes)
  {
    const std::int32_t g = body.nodes[local];
    const double angle = std::atan2(X[2 * g + 1], X[2 * g]);
    if (std::abs(angle - M_PI / 2) < M_PI / 6 + 1e-9)
      top.push_back(g);
    if (std::abs(angle + M_PI / 2) < M_PI / 6 + 1e-9)
      bottom.push_back(g);
  }
  ASSERT_EQ(top.size(), bottom.size());
  const double P = 0.15 * mu * 2 * R;
  for (std::size_t i = 0; i < top.size(); ++i)
  {
    f_ext[2 * top[i] + 1] = -P / top.size();
    f_ext[2 * bottom[i] + 1] = P / bottom.size();
  }

  // Rigid modes: fix the centre node and the x of the top-most node.
  std::int32_t centre = -1, apex = -1;
  for (std::int32_t g : body.nodes)
  {
    if (std::hypot(X[2 * g], X[2 * g + 1]) < 1e-12)
      centre = g;
    if (std::abs(X[2 * g]) < 1e-12 && std::abs(X[2 * g + 1] - R) < 1e-12)
      apex = g;
  }
  ASSERT_GE(centre, 0);
  ASSERT_GE(apex, 0);
  const std::vector<std::int32_t> fixed = {2 * centre, 2 * centre + 1,
                                           2 * apex};
  const std::vector<double> values(3, 0.0);

  bodies::NewtonOptions options;
  options.relative_tolerance = 1e-12;
  const bodies::NewtonHistory h =
      bodies::solve_static_equilibrium(bodies, f_ext, fixed, values, options);
  ASSERT_TRUE(h.converged);
  const std::vector<double>& r = h.residual_norms;
  ASSERT_GE(r.size(), 4u);
  EXPECT_LE(r.size(), 10u) << "Newton should need few iterations";

  // Quadratic convergence: once in the asymptotic range (relative residual
  // below 1e-2, above round-off), log r_{k+1} / log r_k -> 2 in relative terms.
  int checked = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k)
  {
    const double ek = r[k] / r[0], ek1 = r[k + 1] / r[0];
    if (ek < 1e-2 && ek1 > 1e-13)
    {
      EXPECT_GT(std::log(ek1) / std::log(ek), 1.8)
          << "iteration " << k << ": " << ek << " -> " << ek1;
      ++checked;
    }
  }
  EXPECT_GE(checked, 1) << "no iteration in the asymptotic range";

  // The deformed disk is squashed: apex moves down, energy is positive.
  EXPECT_LT(bodies.displacement()[2 * apex + 1], -0.01 * R);
  EXPECT_GT(bodies.strain_energy(), 0.0);
}
