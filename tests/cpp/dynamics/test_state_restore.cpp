// A run continued from a saved state (through the state file) is the run
// that was never interrupted.
#include "scheme_options.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dynamics/moreau_jean.h>
#include <fstream>
#include <gtest/gtest.h>
#include <io/state_file.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
constexpr double R = 0.01, speed = 0.05;

bodies::BodySet two_stacked_disks()
{
  return bodies::BodySet(test::bodies_mesh({test::disk(0, 0, R, 5),
                                            test::disk(0, 2 * R + 1e-5, R, 5)}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), 1180);
}

std::vector<dynamics::Wall> plates()
{
  return {{"bottom", {0, -R - 1e-6}, {0, 1}, {0, 0}},
          {"top", {0, 3 * R + 1e-5 + 1e-6}, {0, -1}, {0, -speed}}};
}

dynamics::MoreauJeanOptions options()
{
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, speed);
  o.damping.alpha = 30;
  o.damping.beta = 1e-5;
  o.time.newton_tolerance = 1e-10;
  o.contact.nlgs_tolerance = 1e-10;
  o.contact.alert_distance = 2e-4;
  // Refactorize at every iteration, so that the restored run (which must
  // refactorize at its first step) does exactly the same operations.
  o.time.full_newton = true;
  return o;
}
} // namespace

TEST(StateFile, ContinuedRunEqualsUninterruptedRun)
{
  const int first = 30, second = 30;
  bodies::BodySet bodies_a = two_stacked_disks();
  dynamics::MoreauJean a(bodies_a, plates(), options());
  for (int s = 0; s < first + second; ++s)
    a.step();

  bodies::BodySet bodies_b = two_stacked_disks();
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "softpack_test_state.bin";
  {
    dynamics::MoreauJean b(bodies_b, plates(), options());
    for (int s = 0; s < first; ++s)
      b.step();
    softpack::io::write_state(path, b.state());
  }
  bodies::BodySet bodies_c = two_stacked_disks();
  dynamics::MoreauJean c(bodies_c, plates(), options());
  c.restore(softpack::io::read_state(path));
  std::filesystem::remove(path);
  EXPECT_EQ(c.steps(), first);
  for (int s = 0; s < second; ++s)
    c.step();

  EXPECT_NEAR(c.time(), a.time(), 1e-15);
  EXPECT_EQ(c.walls()[1].point[1], a.walls()[1].point[1]);
  const std::span<double> ua = bodies_a.displacement(),
                          uc = bodies_c.displacement();
  double scale = 0, diff = 0;
  for (std::size_t i = 0; i < ua.size(); ++i)
  {
    scale = std::max(scale, std::abs(ua[i]));
    diff = std::max(diff, std::abs(ua[i] - uc[i]));
  }
  ASSERT_GT(scale, 1e-4);
  EXPECT_LT(diff, 1e-12 * scale);
  // The energy accounts continue.
  EXPECT_NEAR(c.energy().wall_work / a.energy().wall_work, 1.0, 1e-10);
  EXPECT_NEAR(c.energy().damping / a.energy().damping, 1.0, 1e-10);
}

TEST(StateFile, RefusesWhatIsNotAStateFileOrDoesNotFit)
{
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "softpack_test_not_state.bin";
  std::ofstream(path) << "hello";
  EXPECT_THROW(softpack::io::read_state(path), std::runtime_error);
  std::filesystem::remove(path);

  bodies::BodySet bodies = two_stacked_disks();
  dynamics::MoreauJean scheme(bodies, plates(), options());
  dynamics::SchemeState s = scheme.state();
  s.u.pop_back();
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
}
