// A block pressed on a wall and pushed tangentially: it sticks below
// mu_f N and slides above it, with the Coulomb friction force mu_f N.
#include "scheme_options.h"
#include <bodies/BodySet.h>
#include <bodies/body_forces.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dynamics/moreau_jean.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180, friction = 0.3;
constexpr double width = 0.02, height = 0.005;

struct Block
{
  bodies::BodySet bodies;
  double mass;
};

Block block()
{
  bodies::BodySet b(
      test::bodies_mesh({test::rectangle(0, 0, width, height, 16, 4)}),
      forms::find_material("neo_hookean"), bodies::plane_strain_parameters(mu),
      rho);
  const double m = rho * b.body(0).reference_area;
  return {std::move(b), m};
}

/// Uniform body force (per unit mass) g = (gx, gy), lumped on the nodes.
dynamics::MoreauJeanOptions options(double alpha, double beta)
{
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, 0.01);
  o.damping.alpha = alpha;
  o.damping.beta = beta;
  o.contact.friction = friction;
  o.time.newton_tolerance = 1e-9;
  o.contact.nlgs_tolerance = 1e-10;
  return o;
}

const std::vector<dynamics::Wall> floor_wall = {
    {"floor", {0, 0}, {0, 1}, {0, 0}}};

double mean_vx(const bodies::BodySet& b, std::span<const double> v)
{
  const Eigen::VectorXd& m = b.lumped_mass()[0];
  double p = 0, total = 0;
  for (std::size_t k = 0; k < b.body(0).nodes.size(); ++k)
  {
    p += m[2 * k] * v[2 * b.body(0).nodes[k]];
    total += m[2 * k];
  }
  return p / total;
}
} // namespace

TEST(Friction, BlockSticksBelowTheCoulombThreshold)
{
  Block blk = block();
  const double g = 50, N = blk.mass * g, T = 0.5 * friction * N;
  dynamics::MoreauJean scheme(blk.bodies, floor_wall, options(300, 1e-4));
  scheme.set_external_force(bodies::weight(blk.bodies, {T / blk.mass, -g}));
  for (int s = 0; s < 400; ++s)
    ASSERT_TRUE(scheme.step().newton_converged);
  const auto F = scheme.wall_forces()[0];
  // The floor carries the load and holds the push: tangential force = T.
  // Measured 2026-12-03 (this test): N 6.6e-11 off, T 2.7e-12, the block's
  // mean velocity 1.2e-16 m/s.
  EXPECT_NEAR(F[1] / -N, 1.0, 7e-10);
  EXPECT_NEAR(F[0] / T, 1.0, 3e-11);
  EXPECT_LT(std::abs(mean_vx(blk.bodies, scheme.velocity())), 2e-15);
}

TEST(Friction, BlockSlidesAboveTheThresholdWithForceMuN)
{
  Block blk = block();
  const double g = 50, N = blk.mass * g, T = 2 * friction * N;
  // Stiffness damping calms the block's vibrations (which make a node
  // stick now and then) and leaves its rigid translation free.
  dynamics::MoreauJean scheme(blk.bodies, floor_wall, options(0, 1e-4));
  scheme.set_external_force(bodies::weight(blk.bodies, {T / blk.mass, -g}));
  const int steps = 200;
  for (int s = 0; s < steps; ++s)
  {
    ASSERT_TRUE(scheme.step().newton_converged);
    const auto F = scheme.wall_forces()[0];
    if (s > 20 && F[1] < 0)
      // every contact slides: tangential = mu_f x normal, opposing motion
      // (measured at most 1.7e-16 off, 2026-12-03)
      EXPECT_NEAR(F[0] / -F[1], friction, 2e-15) << "step " << s;
  }
  // Centre of mass: m a = T - mu_f N (the normal force averages to N;
  // measured 7.8e-4 off, 2026-12-03).
  const double a = (T - friction * N) / blk.mass;
  EXPECT_NEAR(mean_vx(blk.bodies, scheme.velocity()) / (a * scheme.time()), 1.0,
              8e-3);
  EXPECT_GT(scheme.energy().friction, 0.0);
}
