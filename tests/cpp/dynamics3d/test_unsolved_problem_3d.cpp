// A 3D contact problem the NLGS leaves unsolved is kept by the step's
// report and written in the FCLIB layout (spacedim 3), as in 2D: read back
// and solved again from its start with the run's options, it fails the
// same way, bit for bit (the replay of raw/failed_contact_problems/ with
// ./softpack fclib --dim 3).
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <contact/fclib_io.h>
#include <dynamics/moreau_jean_options.h>
#include <gtest/gtest.h>
#include <temp_dir.h>

using namespace softpack;

namespace
{
dynamics::MoreauJeanOptions options()
{
  dynamics::MoreauJeanOptions o = test::exact_options(2e-5, 0.5);
  o.contact.alert_distance = 2e-4;
  return o;
}

/// A floor under the pair and a lid on it coming down: both spheres
/// squeezed, each at several nodes
std::vector<dynamics::Wall3D> press()
{
  const double r = test::sphere_radius + 1e-6;
  return {{"floor", {0, 0, -r}, {0, 0, 1}, {0, 0, 0}},
          {"lid", {0, 0, r}, {0, 0, -1}, {0, 0, -0.5}}};
}
} // namespace

TEST(UnsolvedContactProblem3D, IsKeptWrittenAndReplayedBitForBit)
{
  bodies::BodySet bodies = test::spheres("head_on");
  dynamics::MoreauJean converging(bodies, options(), press());
  // On, until several contacts are pressed
  dynamics::StepReport r;
  for (int s = 0; s < 400 && r.active_contacts < 3; ++s)
    r = converging.step();
  ASSERT_GE(r.active_contacts, 3);
  EXPECT_TRUE(r.nlgs_converged);
  EXPECT_FALSE(r.keeps_unsolved_problem());

  // One sweep at a tolerance of 1e-14 cannot solve the pressed pair's
  // coupled contacts: the step's one contact solve fails.
  dynamics::MoreauJeanOptions o = options();
  o.contact.nlgs_max_sweeps = 1;
  o.contact.nlgs_tolerance = 1e-14;
  o.time.newton_max_iterations = 1;
  dynamics::MoreauJean failing(bodies, o, press());
  failing.restore(converging.state());
  r = failing.step();
  ASSERT_FALSE(r.nlgs_converged);
  EXPECT_EQ(r.unsolved_contact_solves, 1);
  EXPECT_FALSE(r.unsolved_problem);
  ASSERT_TRUE(r.unsolved_problem_3d);
  ASSERT_EQ(r.unsolved_problem_3d->num_contacts(),
            failing.contacts_3d().size());

  const test::TempDir dir;
  const std::filesystem::path file = dir.path() / "step.hdf5";
  contact::dump_problem(*r.unsolved_problem_3d, file, "a test",
                        r.unsolved_start);
  const contact::FclibFile3D read = contact::read_fclib_file<3>(file);
  ASSERT_EQ(read.problem.num_contacts(), r.unsolved_problem_3d->num_contacts());
  EXPECT_EQ(read.problem.q, r.unsolved_problem_3d->q);
  EXPECT_EQ(read.problem.friction, r.unsolved_problem_3d->friction);
  ASSERT_TRUE(read.guess_r);
  EXPECT_EQ(*read.guess_r, r.unsolved_start);
  std::vector<double> R = *read.guess_r, U(R.size());
  const contact::NlgsResult again = contact::solve_nlgs(
      read.problem, R, U, dynamics::nlgs_options(o.contact));
  EXPECT_FALSE(again.converged);
  EXPECT_EQ(R, failing.impulses()); // the same failure, bit for bit
}
