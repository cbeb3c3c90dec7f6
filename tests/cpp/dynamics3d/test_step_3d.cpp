// The 3D Moreau–Jean step (issue 40): two elastic spheres (D 20 mm, 198
// nodes each) collide head-on and off-axis. References: the balance of
// momentum (the node-to-face operator's columns sum to zero, the internal
// forces too: momentum is conserved at every Newton iterate, to round-off)
// and of energy (the accounts of driver/energy, theta = 1/2, no damping:
// what the bodies lose is the contacts' dissipation and the strain work's
// quadrature).
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <cmath>
#include <gtest/gtest.h>

using namespace softpack;

namespace
{
struct Collision
{
  double max_momentum_error = 0; ///< |P - P0| / (m v), the largest
  double max_balance = 0;        ///< |energy residual| / kinetic0
  double kinetic0 = 0, kinetic_end = 0;
  double friction = 0, normal = 0;
  int contact_steps = 0;
  double rebound = 0; ///< the spheres' x velocity after, over before
};

/// Spheres 0 (x < 0) and 1 approach along x at +-speed for `steps`
Collision collide(const std::string& mesh, double friction, int steps)
{
  bodies::BodySet bodies = test::spheres(mesh);
  const double speed = 0.5;
  dynamics::MoreauJeanOptions o = test::exact_options(2e-5, speed);
  o.contact.friction = friction;
  o.contact.alert_distance = 2e-4;
  o.time.newton_tolerance = 1e-9;
  o.contact.nlgs_tolerance = 1e-10;
  dynamics::MoreauJean scheme(bodies, o, std::vector<dynamics::Wall3D>{});
  std::vector<double> v(bodies.num_global_dofs(), 0.0);
  const std::span<const double> X = bodies.reference_coordinates();
  for (std::size_t n = 0; n < v.size() / 3; ++n)
    v[3 * n] = X[3 * n] < 0 ? speed : -speed;
  scheme.set_initial_velocity(v);
  const std::array<double, 3> P0 = test::momentum(bodies, scheme.velocity());
  double mass = 0;
  for (const Eigen::VectorXd& m : bodies.lumped_mass())
    mass += m.sum() / 3;
  Collision c;
  for (int s = 0; s < steps; ++s)
  {
    const dynamics::StepReport r = scheme.step();
    EXPECT_TRUE(r.newton_converged) << "step " << s;
    c.contact_steps += r.active_contacts > 0;
    const std::array<double, 3> P = test::momentum(bodies, scheme.velocity());
    for (int i = 0; i < 3; ++i)
      c.max_momentum_error = std::max(c.max_momentum_error,
                                      std::abs(P[i] - P0[i]) / (mass * speed));
    const dynamics::EnergyBalance& e = scheme.energy();
    c.max_balance =
        std::max(c.max_balance, std::abs(e.residual()) / e.kinetic0);
  }
  const dynamics::EnergyBalance& e = scheme.energy();
  c.kinetic0 = e.kinetic0;
  c.kinetic_end = e.kinetic;
  c.friction = e.friction;
  c.normal = e.contact_normal;
  double vx = 0;
  const bodies::Body& right = bodies.body(1);
  for (const std::int32_t n : right.nodes)
    vx += scheme.velocity()[3 * n];
  c.rebound = vx / right.nodes.size() / -speed;
  return c;
}
} // namespace

TEST(Step3D, HeadOnCollisionConservesMomentumAndClosesTheEnergyBalance)
{
  const Collision c = collide("head_on", 0.0, 150);
  RecordProperty("momentum_error", std::to_string(c.max_momentum_error));
  RecordProperty("balance", std::to_string(c.max_balance));
  std::cout << "head-on: momentum " << c.max_momentum_error << ", balance "
            << c.max_balance << ", contact steps " << c.contact_steps
            << ", rebound " << c.rebound << ", normal " << c.normal / c.kinetic0
            << ", kinetic end " << c.kinetic_end / c.kinetic0 << "\n";
  EXPECT_GT(c.contact_steps, 20);
  EXPECT_LT(c.rebound, 0); // they separate
  EXPECT_LT(c.max_momentum_error, 1e-12);
  EXPECT_LT(c.max_balance, 1e-4);
}

TEST(Step3D, OffAxisFrictionalCollisionConservesMomentumAndClosesTheBalance)
{
  const Collision c = collide("off_axis", 0.3, 150);
  std::cout << "off-axis: momentum " << c.max_momentum_error << ", balance "
            << c.max_balance << ", contact steps " << c.contact_steps
            << ", friction " << c.friction / c.kinetic0 << ", normal "
            << c.normal / c.kinetic0 << "\n";
  EXPECT_GT(c.contact_steps, 10);
  EXPECT_GT(c.friction, 0); // sliding dissipates
  EXPECT_LT(c.max_momentum_error, 1e-12);
  EXPECT_LT(c.max_balance, 1e-4);
}

TEST(Step3D, RefusesWhatThe3DStepLacksNamingIt)
{
  bodies::BodySet bodies = test::spheres("head_on");
  const dynamics::MoreauJeanOptions o = test::exact_options(2e-5, 0.5);
  auto message = [](auto&& make)
  {
    try
    {
      make();
    }
    catch (const std::exception& e)
    {
      return std::string(e.what());
    }
    return std::string("nothing thrown");
  };
  EXPECT_NE(message(
                [&]
                {
                  (void)dynamics::MoreauJean(
                      bodies, dynamics::box_walls(-1, 1, -1, 1, 0), o);
                })
                .find("walls: 2D walls"),
            std::string::npos);
  std::vector<dynamics::Wall3D> tilted = {
      {"top", {0, 0, 0.01}, {0, 0.1, -1}, {0, 0, 0}}};
  EXPECT_NE(message([&] { (void)dynamics::MoreauJean(bodies, o, tilted); })
                .find("walls.top.normal"),
            std::string::npos);
  dynamics::MoreauJean scheme(bodies, o, std::vector<dynamics::Wall3D>{});
  dynamics::PeriodicCell cell;
  cell.a1 = {0.1, 0};
  cell.a2 = {0, 0.1};
  EXPECT_NE(message([&] { scheme.set_cell(cell); }).find("not yet in 3D"),
            std::string::npos);
}
