// A 3D run continued from a state file is the uninterrupted run, bit for
// bit: two spheres colliding head-on with friction (the warm start of
// their contacts in world components is in the state) under a moving lid
// (its point is), with modified Newton (the kept iteration matrix is).
#include "../dynamics/same_state.h"
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <gtest/gtest.h>
#include <io/state_file.h>
#include <temp_dir.h>

using namespace softpack;

namespace
{
dynamics::MoreauJeanOptions options()
{
  dynamics::MoreauJeanOptions o = test::exact_options(2e-5, 0.5);
  o.contact.alert_distance = 2e-4;
  // Solves stopped where the start shows: a run without the warm start
  // of the cut's contacts does not continue the same
  o.contact.nlgs_tolerance = 1e-4;
  o.time.full_newton = false; // the kept matrix crosses the cut
  o.time.tangent_reuse_steps = 8;
  return o;
}

/// A lid far above the spheres, coming down
std::vector<dynamics::Wall3D> lid()
{
  return {{"lid", {0, 0, 0.05}, {0, 0, -1}, {0, 0, -0.1}}};
}

/// The head-on pair approaching along x at +-0.5 m/s
void approach(dynamics::MoreauJean& scheme, const bodies::BodySet& bodies)
{
  std::vector<double> v(bodies.num_global_dofs(), 0.0);
  const std::span<const double> X = bodies.reference_coordinates();
  for (std::size_t n = 0; n < v.size() / 3; ++n)
    v[3 * n] = X[3 * n] < 0 ? 0.5 : -0.5;
  scheme.set_initial_velocity(v);
}

void advance(dynamics::MoreauJean& scheme, int steps)
{
  for (int s = 0; s < steps; ++s)
    scheme.step();
}
} // namespace

TEST(ContinuedRun3D, EqualsUninterruptedRun)
{
  const int first = 100, second = 30; // 2 active contacts at the cut
  bodies::BodySet bodies_a = test::spheres("head_on");
  dynamics::MoreauJean a(bodies_a, options(), lid());
  approach(a, bodies_a);
  advance(a, first + second);

  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "state.bin";
  {
    bodies::BodySet bodies_b = test::spheres("head_on");
    dynamics::MoreauJean b(bodies_b, options(), lid());
    approach(b, bodies_b);
    advance(b, first);
    const dynamics::SchemeState saved = b.state();
    EXPECT_EQ(saved.dim, 3);
    // Contacts carrying impulses at the cut (without their warm start the
    // continued run differs: 2e-14 m in u 60 steps on, measured)
    ASSERT_GT(saved.reactions_3d.size(), 0u);
    EXPECT_GT(std::abs(saved.reactions_3d[0].second[0]) +
                  std::abs(saved.reactions_3d.back().second[0]),
              0.0);
    EXPECT_GE(saved.matrix_age, 0);
    ASSERT_EQ(saved.wall_points_3d.size(), 1u);
    io::write_state(path, saved);
  }
  bodies::BodySet bodies_c = test::spheres("head_on");
  dynamics::MoreauJean c(bodies_c, options(), lid());
  c.restore(io::read_state(path));
  EXPECT_EQ(c.steps(), first);
  advance(c, second);

  EXPECT_EQ(c.time(), a.time());
  EXPECT_EQ(c.walls_3d()[0].point[2], a.walls_3d()[0].point[2]);
  EXPECT_NE(c.walls_3d()[0].point[2], 0.05);
  test::expect_same_displacement(bodies_a.displacement(),
                                 bodies_c.displacement());
  EXPECT_EQ(c.velocity()[0], a.velocity()[0]);
  EXPECT_EQ(c.energy().friction, a.energy().friction);
  EXPECT_EQ(c.energy().contact_normal, a.energy().contact_normal);
  EXPECT_GT(a.energy().friction, 0); // the contacts slid
}

TEST(ContinuedRun3D, AStateOfAnotherDimensionOrBoxIsRefused)
{
  bodies::BodySet bodies = test::spheres("head_on");
  dynamics::MoreauJean scheme(bodies, options(), lid());
  dynamics::SchemeState s = scheme.state();
  s.dim = 2;
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
  s = scheme.state();
  s.wall_points_3d.push_back({0, 0, 0});
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
  s = scheme.state();
  s.u.pop_back();
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
  EXPECT_NO_THROW(scheme.restore(scheme.state()));
}
