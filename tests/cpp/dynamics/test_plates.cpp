// Disks compressed between rigid plates: non-penetration, action and
// reaction, equilibrium at rest, and the energy balance.
#include "scheme_options.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <cstdio>
#include <dynamics/moreau_jean.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180, R = 0.01;
constexpr double speed = 0.05; // plate speed (m/s)

bodies::BodySet column_of_disks(int n)
{
  std::vector<test::Triangulation> parts;
  for (int i = 0; i < n; ++i)
    parts.push_back(test::disk(0, i * (2 * R + 1e-5), R, 6));
  return bodies::BodySet(test::bodies_mesh(parts),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
}

dynamics::MoreauJeanOptions options(double alpha)
{
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, speed);
  o.time.theta = 0.55;
  o.damping.alpha = alpha;
  o.damping.beta = 1e-5;
  o.time.newton_tolerance = 1e-8;
  o.contact.alert_distance = 2e-4;
  return o;
}

/// Plates at y = -R (fixed) and just above the top disk (moving down).
std::vector<dynamics::Wall> plates(int n)
{
  const double top = (n - 1) * (2 * R + 1e-5) + R + 1e-6;
  return {{"bottom", {0, -R - 1e-6}, {0, 1}, {0, 0}},
          {"top", {0, top}, {0, -1}, {0, -speed}}};
}

/// Press by `approach`, stop the plate and let the damping bring the
/// bodies to rest. `max_residual`: the largest |energy residual| after any
/// step.
void press_and_settle(dynamics::MoreauJean& scheme, double approach,
                      int settle_steps, double& max_penetration,
                      double* max_residual = nullptr)
{
  const int press_steps = static_cast<int>(
      std::round(approach / (speed * scheme.options().time.time_step)));
  max_penetration = 0;
  if (max_residual)
    *max_residual = 0;
  for (int s = 0; s < press_steps + settle_steps; ++s)
  {
    if (s == press_steps)
      scheme.walls()[1].velocity = {0, 0};
    const dynamics::StepReport r = scheme.step();
    max_penetration = std::max(max_penetration, r.max_penetration);
    if (max_residual)
      *max_residual =
          std::max(*max_residual, std::abs(scheme.energy().residual()));
    ASSERT_TRUE(r.newton_converged) << "step " << s;
    ASSERT_TRUE(r.nlgs_converged)
        << "step " << s << ": NLGS error " << r.nlgs_error << " after "
        << r.nlgs_iterations << " sweeps";
  }
}

/// Resultant contact force on body b (from the last step's impulses).
std::array<double, 2> contact_resultant(const dynamics::MoreauJean& scheme,
                                        int b, int from_body = -2)
{
  std::array<double, 2> f = {0, 0};
  const double h = scheme.time_step(); // of the last step
  for (std::size_t a = 0; a < scheme.contacts().size(); ++a)
  {
    const dynamics::Contact& c = scheme.contacts()[a];
    const double rn = scheme.impulses()[2 * a],
                 rt = scheme.impulses()[2 * a + 1];
    const std::array<double, 2> force = {(rn * c.n[0] + rt * c.t[0]) / h,
                                         (rn * c.n[1] + rt * c.t[1]) / h};
    double sign = 0;
    if (c.candidate_body == b &&
        (from_body == -2 || c.antagonist_body == from_body))
      sign = 1;
    if (c.antagonist_body == b &&
        (from_body == -2 || c.candidate_body == from_body))
      sign = -1;
    f[0] += sign * force[0];
    f[1] += sign * force[1];
  }
  return f;
}
} // namespace

TEST(Plates, DiskBetweenPlatesComesToRestInEquilibrium)
{
  bodies::BodySet bodies = column_of_disks(1);
  // Heavy mass damping (decay rate alpha/2) so that 300 steps reach rest.
  dynamics::MoreauJean scheme(bodies, plates(1), options(3000));
  double penetration;
  press_and_settle(scheme, 1e-3, 300, penetration);

  // Non-penetration at the tolerance of the contact solve.
  EXPECT_LT(penetration, 1e-12); // measured 1.1e-13 m (this test, 2026-12-03)
  const auto forces = scheme.wall_forces();
  const double F = forces[1][1]; // the top plate is pushed up
  ASSERT_GT(F, 0.0);
  // Action and reaction through the disk: the plates carry opposite forces.
  EXPECT_NEAR(forces[0][1] / F, -1.0, 2e-13); // measured 1.8e-14 (2026-12-03)
  // The body at rest: its contact forces sum to zero, its velocity vanishes.
  const auto resultant = contact_resultant(scheme, 0);
  EXPECT_LT(std::hypot(resultant[0], resultant[1]) / F,
            3e-11); // measured 2.8e-12 (this test, 2026-12-03)
  double vmax = 0;
  for (double v : scheme.velocity())
    vmax = std::max(vmax, std::abs(v));
  EXPECT_LT(vmax, 2e-10 * speed); // measured 1.3e-11 speed (2026-12-03)
  std::printf("one disk at rest: penetration %.2e m, plates %.2e, resultant "
              "%.2e, v/speed %.2e\n",
              penetration, forces[0][1] / F + 1,
              std::hypot(resultant[0], resultant[1]) / F, vmax / speed);
}

TEST(Plates, StackedDisksTransmitTheForceFromBodyToBody)
{
  bodies::BodySet bodies = column_of_disks(2);
  dynamics::MoreauJean scheme(bodies, plates(2), options(3000));
  double penetration;
  press_and_settle(scheme, 1e-3, 700, penetration);
  EXPECT_LT(penetration, 1e-12); // measured 4.2e-14 m (this test, 2026-12-03)

  const auto forces = scheme.wall_forces();
  const double F = forces[1][1];
  ASSERT_GT(F, 0.0);
  const auto on_lower_from_upper = contact_resultant(scheme, 0, 1);
  const auto on_upper_from_lower = contact_resultant(scheme, 1, 0);
  // Action = reaction between the two bodies (the same impulses summed
  // with opposite signs: measured exactly 0, 2026-12-03)
  EXPECT_NEAR(on_lower_from_upper[1], -on_upper_from_lower[1], 1e-12 * F);
  // ... and the lower body passes it on to the floor: it is at rest (what
  // is left is the damping of the settling stack).
  EXPECT_NEAR(on_lower_from_upper[1] / F, -1.0,
              2e-7); // measured 1.8e-8 (this test, 2026-12-03)
  EXPECT_NEAR(forces[0][1] / F, -1.0,
              4e-7); // measured 3.6e-8 (this test, 2026-12-03)
  std::printf("two disks at rest: penetration %.2e m, lower body %.2e, "
              "floor %.2e\n",
              penetration, on_lower_from_upper[1] / F + 1,
              forces[0][1] / F + 1);
}

TEST(Plates, EnergyBalanceClosesOverACompression)
{
  bodies::BodySet bodies = column_of_disks(2);
  dynamics::MoreauJean scheme(bodies, plates(2), options(30));
  double penetration, max_residual;
  press_and_settle(scheme, 2e-3, 0, penetration, &max_residual);
  const dynamics::EnergyBalance& e = scheme.energy();
  ASSERT_GT(e.wall_work, 0.0);
  EXPECT_GT(e.strain, 0.5 * e.wall_work);
  // At every step (the work is 0 until the plate touches: the bound is on
  // the final work) and at the end. Measured 2026-12-03: at most 1.6e-7 of
  // the final work over the steps, 1.6e-7 of it at the end; with the
  // stiffness part of the dissipation dropped from the accounts 5.7e-4
  // (tried 2026-12-03), which the former 1 % let pass.
  EXPECT_LT(max_residual, 2e-6 * e.wall_work);
  std::printf("compression: |residual| / wall work = %.2e (end), %.2e (largest "
              "over the steps)\n",
              std::abs(e.residual()) / e.wall_work, max_residual / e.wall_work);
  EXPECT_LT(std::abs(e.residual()), 2e-6 * e.wall_work)
      << "wall work " << e.wall_work << ", strain " << e.strain << ", kinetic "
      << e.kinetic << ", damping " << e.damping << ", friction " << e.friction
      << ", normal " << e.contact_normal;
}
