// A run continued from a saved state (through the state file) is the run
// that was never interrupted.
#include "same_state.h"
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
#include <temp_dir.h>
#include <vector>

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

/// How the continued run steps.
enum class Stepping
{
  full_newton,
  modified_newton,
  adaptive_step ///< modified Newton on steps from 1e-4 to 4e-4 s
};

dynamics::MoreauJeanOptions options(Stepping stepping)
{
  const bool full_newton = stepping == Stepping::full_newton;
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, speed);
  o.damping.alpha = 30;
  o.damping.beta = 1e-5;
  o.time.newton_tolerance = 1e-10;
  o.contact.nlgs_tolerance = 1e-10;
  o.contact.alert_distance = 2e-4;
  o.time.full_newton = full_newton;
  if (!full_newton)
  {
    // Modified Newton as the schema's defaults run it: the matrix kept for
    // several steps, refactored early after a slow step.
    o.time.tangent_reuse_steps = 20;
    o.time.refactor_above_iterations = 5;
  }
  if (stepping == Stepping::adaptive_step)
  {
    // Tolerances at which the calm steps need two Newton iterations.
    o.time.max_step_factor = 4;
    o.time.newton_tolerance = 1e-5;
    o.contact.nlgs_tolerance = 1e-7;
  }
  return o;
}

/// Steps `n` steps; the steps at which the iteration matrix was refactored.
std::vector<long> advance(dynamics::MoreauJean& scheme, int n)
{
  std::vector<long> refactored;
  for (int s = 0; s < n; ++s)
    if (scheme.step().refactorized)
      refactored.push_back(scheme.steps());
  return refactored;
}
} // namespace

/// A run continued from a state file takes the same steps, bit for bit, as
/// the run never interrupted: with full Newton, and with modified Newton,
/// whose kept iteration matrix (assembled steps before the state) and
/// refactor decisions are part of the state; and with an adaptive step,
/// whose size and window are.
class ContinuedRun : public testing::TestWithParam<Stepping>
{
};

TEST_P(ContinuedRun, EqualsUninterruptedRun)
{
  const Stepping stepping = GetParam();
  const int first = 30, second = 30;
  bodies::BodySet bodies_a = two_stacked_disks();
  dynamics::MoreauJean a(bodies_a, plates(), options(stepping));
  advance(a, first);
  const std::vector<long> refactored_a = advance(a, second);

  bodies::BodySet bodies_b = two_stacked_disks();
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "state.bin";
  {
    dynamics::MoreauJean b(bodies_b, plates(), options(stepping));
    advance(b, first);
    const dynamics::SchemeState saved = b.state();
    if (stepping != Stepping::full_newton) // a matrix is kept at the cut
      EXPECT_GT(saved.matrix_age, 0);
    softpack::io::write_state(path, saved);
  }
  bodies::BodySet bodies_c = two_stacked_disks();
  dynamics::MoreauJean c(bodies_c, plates(), options(stepping));
  c.restore(softpack::io::read_state(path));
  EXPECT_EQ(c.steps(), first);
  EXPECT_EQ(advance(c, second), refactored_a);

  EXPECT_EQ(c.time(), a.time());
  if (stepping == Stepping::adaptive_step) // the step did adapt
    EXPECT_GT(a.time(), (first + second) * 1.5e-4);
  EXPECT_EQ(c.walls()[1].point[1], a.walls()[1].point[1]);
  test::expect_same_displacement(bodies_a.displacement(),
                                 bodies_c.displacement());
  EXPECT_EQ(c.velocity()[0], a.velocity()[0]);
  // The energy accounts continue.
  EXPECT_EQ(c.energy().wall_work, a.energy().wall_work);
  EXPECT_EQ(c.energy().damping, a.energy().damping);
}

INSTANTIATE_TEST_SUITE_P(StateFile, ContinuedRun,
                         testing::Values(Stepping::full_newton,
                                         Stepping::modified_newton,
                                         Stepping::adaptive_step),
                         [](const testing::TestParamInfo<Stepping>& p)
                         {
                           return p.param == Stepping::full_newton
                                      ? "FullNewton"
                                  : p.param == Stepping::modified_newton
                                      ? "ModifiedNewton"
                                      : "AdaptiveStep";
                         });

TEST(StateFile, RefusesWhatIsNotAStateFileOrDoesNotFit)
{
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "not_state.bin";
  std::ofstream(path) << "hello";
  EXPECT_THROW(softpack::io::read_state(path), std::runtime_error);

  bodies::BodySet bodies = two_stacked_disks();
  dynamics::MoreauJean scheme(bodies, plates(),
                              options(Stepping::modified_newton));
  dynamics::SchemeState s = scheme.state();
  s.u.pop_back();
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
  // A kept tangent of another size
  s = scheme.state();
  s.matrix_age = 3;
  s.u_tangent.assign(s.u.size() + 1, 0.0);
  EXPECT_THROW(scheme.restore(s), std::invalid_argument);
}

TEST(StateFile, AFullDiskIsSaidAndLeavesNoPartialFile)
{
  // The temporary file is a link to /dev/full: every write is ENOSPC.
  const test::TempDir dir;
  const std::filesystem::path path = dir.path() / "state.bin",
                              tmp = dir.path() / "state.bin.tmp";
  std::filesystem::create_symlink("/dev/full", tmp);
  bodies::BodySet bodies = two_stacked_disks();
  dynamics::MoreauJean scheme(bodies, plates(),
                              options(Stepping::modified_newton));
  try
  {
    softpack::io::write_state(path, scheme.state());
    FAIL() << "no error on a full disk";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("No space left on device"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(tmp)));
  EXPECT_FALSE(std::filesystem::exists(path));
}

/// A step that cannot be solved at its size is started again from the same
/// start at half the size, down to time.time_step: with one Newton
/// iteration allowed no step converges, so a step begun at 4e-4 s is tried
/// at 4e-4, 2e-4 and 1e-4 s and kept at 1e-4 s, unsolved, bit for bit the
/// step of a run on fixed 1e-4-s steps.
TEST(AdaptiveStep, AnUnsolvedStepIsRetriedAtHalfTheSizeDownToTheBase)
{
  // Full Newton: both runs factorize at the step's start, at 1e-4 s.
  dynamics::MoreauJeanOptions fixed = options(Stepping::full_newton);
  fixed.time.newton_max_iterations = 1;
  dynamics::MoreauJeanOptions adaptive = fixed;
  adaptive.time.max_step_factor = 4;

  bodies::BodySet bodies_a = two_stacked_disks(),
                  bodies_b = two_stacked_disks();
  dynamics::MoreauJean a(bodies_a, plates(), fixed);
  dynamics::MoreauJean b(bodies_b, plates(), adaptive);
  // Both start touching: advance to contact on fixed steps, then give b
  // a current step of 4e-4 s through its state.
  advance(a, 25);
  dynamics::SchemeState s = a.state();
  s.step_size.h = 4e-4;
  b.restore(s);
  const dynamics::StepReport ra = a.step(), rb = b.step();
  ASSERT_GT(ra.contacts, 0);
  EXPECT_FALSE(ra.newton_converged);
  EXPECT_EQ(rb.retries, 2);
  EXPECT_EQ(rb.time_step, 1e-4);
  EXPECT_FALSE(rb.newton_converged);
  EXPECT_EQ(b.time(), a.time());
  const std::span<double> ua = bodies_a.displacement(),
                          ub = bodies_b.displacement();
  for (std::size_t i = 0; i < ua.size(); ++i)
    ASSERT_EQ(ua[i], ub[i]) << i;
}
