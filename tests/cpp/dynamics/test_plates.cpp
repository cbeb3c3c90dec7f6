// Disks compressed between rigid plates: non-penetration, action and
// reaction, equilibrium at rest, and the energy balance.
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
/// bodies to rest.
void press_and_settle(dynamics::MoreauJean& scheme, double approach,
                      int settle_steps, double& max_penetration)
{
  const int press_steps = static_cast<int>(
      std::round(approach / (speed * scheme.options().time.time_step)));
  max_penetration = 0;
  for (int s = 0; s < press_steps + settle_steps; ++s)
  {
    if (s == press_steps)
      scheme.walls()[1].velocity = {0, 0};
    const dynamics::StepReport r = scheme.step();
    max_penetration = std::max(max_penetration, r.max_penetration);
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
  EXPECT_LT(penetration, 1e-9);
  const auto forces = scheme.wall_forces();
  const double F = forces[1][1]; // the top plate is pushed up
  ASSERT_GT(F, 0.0);
  // Action and reaction through the disk: the plates carry opposite forces.
  EXPECT_NEAR(forces[0][1] / F, -1.0, 1e-4);
  // The body at rest: its contact forces sum to zero, its velocity vanishes.
  const auto resultant = contact_resultant(scheme, 0);
  EXPECT_LT(std::hypot(resultant[0], resultant[1]) / F, 1e-4);
  double vmax = 0;
  for (double v : scheme.velocity())
    vmax = std::max(vmax, std::abs(v));
  EXPECT_LT(vmax, 1e-4 * speed);
}

TEST(Plates, StackedDisksTransmitTheForceFromBodyToBody)
{
  bodies::BodySet bodies = column_of_disks(2);
  dynamics::MoreauJean scheme(bodies, plates(2), options(3000));
  double penetration;
  press_and_settle(scheme, 1e-3, 700, penetration);
  EXPECT_LT(penetration, 1e-9);

  const auto forces = scheme.wall_forces();
  const double F = forces[1][1];
  ASSERT_GT(F, 0.0);
  const auto on_lower_from_upper = contact_resultant(scheme, 0, 1);
  const auto on_upper_from_lower = contact_resultant(scheme, 1, 0);
  // Action = reaction between the two bodies
  EXPECT_NEAR(on_lower_from_upper[1], -on_upper_from_lower[1], 1e-12 * F);
  // ... and the lower body passes it on to the floor: it is at rest.
  EXPECT_NEAR(on_lower_from_upper[1] / F, -1.0, 1e-4);
  EXPECT_NEAR(forces[0][1] / F, -1.0, 1e-4);
}

TEST(Plates, EnergyBalanceClosesOverACompression)
{
  bodies::BodySet bodies = column_of_disks(2);
  dynamics::MoreauJean scheme(bodies, plates(2), options(30));
  double penetration;
  press_and_settle(scheme, 2e-3, 0, penetration);
  const dynamics::EnergyBalance& e = scheme.energy();
  ASSERT_GT(e.wall_work, 0.0);
  EXPECT_GT(e.strain, 0.5 * e.wall_work);
  EXPECT_LT(std::abs(e.residual()), 0.01 * e.wall_work)
      << "wall work " << e.wall_work << ", strain " << e.strain << ", kinetic "
      << e.kinetic << ", damping " << e.damping << ", friction " << e.friction
      << ", normal " << e.contact_normal;
}
