// Contact forces averaged over an output interval: they are the impulses
// summed over the interval divided by its duration, they balance the
// body's change of momentum (the exact discrete momentum balance), and they
// remove the step-to-step alternation of theta = 1/2.
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dynamics/contact_history.h>
#include <dynamics/moreau_jean.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180, R = 0.01, speed = 0.05;
constexpr double alpha = 30, theta = 0.5;

dynamics::MoreauJeanOptions paper_like_options()
{
  dynamics::MoreauJeanOptions o;
  o.time_step = 1e-4;
  o.theta = theta;
  o.alpha = alpha;
  o.beta = 1e-5;
  o.friction = 0.3;
  o.velocity_scale = speed;
  o.newton_tolerance = 1e-10;
  o.detection.alert_distance = 2e-4;
  o.nlgs.tolerance = 1e-10;
  return o;
}

/// Momentum of the single body along y: 1^T M v (the row sums of the
/// consistent P1 mass are the lumped mass).
double momentum_y(const bodies::BodySet& bodies, dynamics::MoreauJean& scheme)
{
  const bodies::Body& body = bodies.body(0);
  const Eigen::VectorXd& m = bodies.lumped_mass()[0];
  double p = 0;
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
    p += m[2 * k + 1] * scheme.velocity()[2 * body.nodes[k] + 1];
  return p;
}

/// Resultant on the body (the candidate of every contact here).
std::array<double, 2>
resultant(const std::vector<dynamics::AveragedContactForce>& forces)
{
  std::array<double, 2> f = {0, 0};
  for (const dynamics::AveragedContactForce& c : forces)
  {
    f[0] += c.force[0];
    f[1] += c.force[1];
  }
  return f;
}
} // namespace

TEST(ContactForceAverage, BalancesMomentumAndRemovesTheAlternation)
{
  bodies::BodySet bodies(test::bodies_mesh({test::disk(0, 0, R, 6)}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
  std::vector<dynamics::Wall> walls = {
      {"bottom", {0, -R - 1e-6}, {0, 1}, {0, 0}},
      {"top", {0, R + 1e-6}, {0, -1}, {0, -speed}}};
  dynamics::MoreauJean scheme(bodies, walls, paper_like_options());
  const double h = scheme.options().time_step;

  // Press by 1 mm, stop the plate, hold.
  const int press = 200, hold = 400, interval = 100;
  dynamics::ContactForceAverage average;
  double p0 = 0, damping_sum = 0, p_prev = 0;
  std::vector<double> instantaneous_resultant;
  std::array<double, 2> wall_sum[2] = {{0, 0}, {0, 0}};
  for (int s = 0; s < press + hold; ++s)
  {
    if (s == press)
      scheme.walls()[1].velocity = {0, 0};
    const bool in_interval = s >= press + hold - interval;
    if (s == press + hold - interval)
    {
      average.reset();
      p0 = p_prev = momentum_y(bodies, scheme);
    }
    ASSERT_TRUE(scheme.step().newton_converged);
    average.add_step(scheme);
    if (!in_interval)
      continue;
    const double p = momentum_y(bodies, scheme);
    damping_sum += h * alpha * (theta * p + (1 - theta) * p_prev);
    p_prev = p;
    const auto f = scheme.wall_forces();
    for (int w = 0; w < 2; ++w)
      for (int d = 0; d < 2; ++d)
        wall_sum[w][d] += f[w][d] / interval;
    instantaneous_resultant.push_back(-f[0][1] - f[1][1]);
  }
  ASSERT_NEAR(average.duration(), interval * h, 1e-15);

  // The averaged wall forces are the means of the per-step ones.
  const auto wall = average.wall_forces();
  const double F = wall[1][1];
  ASSERT_GT(F, 0.0);
  for (int w = 0; w < 2; ++w)
    for (int d = 0; d < 2; ++d)
      EXPECT_NEAR(wall[w][d], wall_sum[w][d], 1e-12 * F);

  // Action and reaction: the body's averaged contact forces are the
  // opposite of what the walls receive.
  const auto forces = average.contact_forces();
  const auto f = resultant(forces);
  EXPECT_NEAR(f[1], -(wall[0][1] + wall[1][1]), 1e-12 * F);

  // The discrete momentum balance along y (internal and stiffness-damping
  // forces of a body sum to zero): sum of impulses = p_end - p_start +
  // h alpha sum(theta p+ + (1 - theta) p-).
  const double impulse = f[1] * average.duration();
  const double p1 = momentum_y(bodies, scheme);
  EXPECT_NEAR(impulse, p1 - p0 + damping_sum, 1e-6 * F * h);

  // The alternation of single steps averages out: what is left is the
  // body's true (slowly decaying) change of momentum, checked just above.
  // Measured: averaged 3.3e-3 of the plate force, single steps up to 7e-2.
  double worst = 0;
  for (double r : instantaneous_resultant)
    worst = std::max(worst, std::abs(r) / F);
  EXPECT_LT(std::abs(f[1]) / F, 0.1 * worst);
  std::printf("resultant / plate force: averaged %.2e, worst single step "
              "%.2e\n",
              std::abs(f[1]) / F, worst);
}
