// A body with no contact: momentum is conserved without damping, and a rigid
// translation decays at the rate alpha of the mass-proportional damping.
#include "scheme_options.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dynamics/moreau_jean.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180, R = 0.01;

bodies::BodySet free_disk()
{
  return bodies::BodySet(test::bodies_mesh({test::disk(0, 0, R, 4)}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
}

/// Total linear momentum M v (consistent mass).
std::array<double, 2> momentum(const bodies::BodySet& bodies,
                               std::span<const double> v)
{
  const bodies::Body& body = bodies.body(0);
  Eigen::VectorXd vb(body.num_dofs());
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
    for (int c = 0; c < 2; ++c)
      vb[2 * k + c] = v[2 * body.nodes[k] + c];
  const Eigen::VectorXd p =
      bodies::symmetric_product(bodies.consistent_mass()[0], vb);
  std::array<double, 2> P = {0, 0};
  for (int i = 0; i < p.size(); ++i)
    P[i % 2] += p[i];
  return P;
}
} // namespace

TEST(FreeBody, MomentumIsConservedWithoutDamping)
{
  bodies::BodySet bodies = free_disk();
  dynamics::MoreauJeanOptions options = test::exact_options(2e-4, 1e-3);
  options.time.newton_tolerance = 1e-10;
  dynamics::MoreauJean scheme(bodies, {}, options);
  // Translation + spin + a vibration mode: the body deforms and rotates.
  std::span<const double> X = bodies.reference_coordinates();
  std::vector<double> v(X.size());
  for (std::size_t i = 0; i < X.size() / 2; ++i)
  {
    const double x = X[2 * i], y = X[2 * i + 1];
    v[2 * i] = 0.3 - 20 * y + 5 * x;
    v[2 * i + 1] = -0.1 + 20 * x - 5 * y;
  }
  scheme.set_initial_velocity(v);
  const std::array<double, 2> P0 = momentum(bodies, v);
  for (int s = 0; s < 40; ++s)
  {
    const dynamics::StepReport r = scheme.step();
    ASSERT_TRUE(r.newton_converged) << "step " << s;
  }
  const std::array<double, 2> P = momentum(bodies, scheme.velocity());
  const double scale = std::hypot(P0[0], P0[1]);
  // measured 1.2e-16 of the momentum (this test, 2026-12-03)
  EXPECT_NEAR(P[0], P0[0], 2e-15 * scale);
  EXPECT_NEAR(P[1], P0[1], 2e-15 * scale);
  // Energy: theta = 1/2 conserves it up to the quadrature of the strain work
  // (measured 8.1e-7 of the initial kinetic energy, 2026-12-03).
  const dynamics::EnergyBalance& e = scheme.energy();
  EXPECT_GT(e.strain, 0.0);
  EXPECT_LT(std::abs(e.residual()), 1e-5 * e.kinetic0);
}

TEST(FreeBody, TranslationDecaysAtTheRateAlpha)
{
  bodies::BodySet bodies = free_disk();
  dynamics::MoreauJeanOptions options = test::exact_options(1e-3, 1e-3);
  options.damping.alpha = 30;
  options.damping.beta = 1e-5;
  dynamics::MoreauJean scheme(bodies, {}, options);
  std::vector<double> v(bodies.num_dofs(), 0.0);
  for (std::size_t i = 0; i < v.size(); i += 2)
    v[i] = 0.2;
  scheme.set_initial_velocity(v);
  for (int s = 1; s <= 100; ++s)
  {
    scheme.step();
    const double expected =
        0.2 * std::exp(-options.damping.alpha * scheme.time());
    for (std::size_t i = 0; i < v.size(); i += 2)
    {
      // theta = 1/2 is second order: relative error ~ t alpha (h alpha)^2/12
      // (measured at most 2.25e-4 over the 100 steps, 2026-12-03); no
      // transverse velocity (measured 4.9e-14 m/s)
      ASSERT_NEAR(scheme.velocity()[i] / expected, 1.0, 1e-3) << "step " << s;
      ASSERT_NEAR(scheme.velocity()[i + 1], 0.0, 5e-13);
    }
  }
  // The kinetic energy lost went into damping (measured 1.3e-14 apart).
  const dynamics::EnergyBalance& e = scheme.energy();
  EXPECT_NEAR(e.damping / (e.kinetic0 - e.kinetic), 1.0, 2e-13);
}

TEST(FreeBody, OptionsOutsideTheSchemaAreRefused)
{
  bodies::BodySet bodies = free_disk();
  dynamics::MoreauJeanOptions options = test::exact_options(1e-4, 1e-3);
  options.time.theta = 0.4;
  EXPECT_THROW(
      {
        try
        {
          dynamics::MoreauJean(bodies, {}, options);
        }
        catch (const std::runtime_error& e)
        {
          EXPECT_NE(std::string(e.what()).find("time.theta"), std::string::npos)
              << e.what();
          throw;
        }
      },
      std::runtime_error);
  options.time.theta = 0.5;
  options.velocity_scale = 0;
  EXPECT_THROW(dynamics::MoreauJean(bodies, {}, options),
               std::invalid_argument);
}
