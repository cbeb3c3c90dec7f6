// The 3D step over MPI ranks (docs/mpi_design.md, "3D runs"; CTest runs
// this executable alone, the one-rank case, and under mpirun -np 2): two
// spheres collide off-axis with friction, each rank owning one, and every
// step gives the serial run's contacts (one vertex on a face, ~100 steps),
// impulses, boundary velocities and energies (the serial run on MPI_COMM_SELF
// in every process).
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <parallel/distribution.h>

using namespace softpack;

namespace
{
dynamics::MoreauJeanOptions collision_options()
{
  dynamics::MoreauJeanOptions o = test::exact_options(2e-5, 0.5);
  o.contact.alert_distance = 2e-4;
  o.time.full_newton = false; // lagged tangents, and refactorizations
  o.time.tangent_reuse_steps = 10;
  return o;
}

/// Sphere 0 (x < 0) and 1 approach along x at +-0.5 m/s
void start(dynamics::MoreauJean& scheme, const bodies::BodySet& whole)
{
  std::vector<double> v(whole.num_global_dofs(), 0.0);
  const std::span<const double> X = whole.reference_coordinates();
  for (std::size_t n = 0; n < v.size() / 3; ++n)
    v[3 * n] = X[3 * n] < 0 ? 0.5 : -0.5;
  scheme.set_initial_velocity(v);
}

/// |a - b| relative to the larger magnitude (1 when both are 0: exact)
double relative(double a, double b)
{
  const double scale = std::max({std::abs(a), std::abs(b), 1e-300});
  return std::abs(a - b) / scale;
}
} // namespace

TEST(Step3DRanks, AnOffAxisCollisionIsTheSerialOne)
{
  bodies::BodySet whole = test::spheres("off_axis");
  dynamics::MoreauJean serial(whole, collision_options(),
                              std::vector<dynamics::Wall3D>{});
  bodies::BodySet bodies = test::spheres("off_axis");
  dynamics::MoreauJean scheme(bodies, collision_options(),
                              std::vector<dynamics::Wall3D>{},
                              parallel::Distribution(MPI_COMM_WORLD, bodies));
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  EXPECT_EQ(static_cast<int>(bodies.local_bodies().size()), ranks == 1   ? 2
                                                            : ranks == 2 ? 1
                                                                         : 0);
  start(serial, whole);
  start(scheme, whole);
  int contact_steps = 0;
  double worst_R = 0, worst_v = 0, worst_E = 0;
  for (int s = 0; s < 220; ++s)
  {
    const dynamics::StepReport r0 = serial.step();
    const dynamics::StepReport r = scheme.step();
    ASSERT_TRUE(r.newton_converged && r.nlgs_converged) << "step " << s;
    EXPECT_EQ(r.newton_iterations, r0.newton_iterations) << "step " << s;
    ASSERT_EQ(scheme.contacts_3d().size(), serial.contacts_3d().size())
        << "step " << s;
    contact_steps += r.active_contacts > 0;
    for (std::size_t a = 0; a < serial.contacts_3d().size(); ++a)
    {
      const dynamics::Contact3D &c = scheme.contacts_3d()[a],
                                &c0 = serial.contacts_3d()[a];
      EXPECT_EQ(c.candidate_body, c0.candidate_body);
      EXPECT_EQ(c.candidate_node, c0.candidate_node);
      EXPECT_EQ(c.triangle, c0.triangle);
    }
    double R_scale = 1e-300;
    for (const double R : serial.impulses())
      R_scale = std::max(R_scale, std::abs(R));
    for (std::size_t k = 0; k < serial.impulses().size(); ++k)
      worst_R = std::max(worst_R,
                         std::abs(scheme.impulses()[k] - serial.impulses()[k]) /
                             R_scale);
    for (int b = 0; b < 2; ++b) // the boundaries: on every rank
      for (const std::int32_t k : whole.body(b).boundary_nodes)
        for (int c = 0; c < 3; ++c)
          worst_v = std::max(
              worst_v,
              std::abs(scheme.velocity()[3 * bodies.body(b).nodes[k] + c] -
                       serial.velocity()[3 * whole.body(b).nodes[k] + c]));
    scheme.prepare_output();
    serial.prepare_output();
    const dynamics::EnergyBalance &e = scheme.energy(), &e0 = serial.energy();
    for (const auto& [x, x0] :
         {std::pair{e.kinetic, e0.kinetic}, std::pair{e.strain, e0.strain},
          std::pair{e.friction, e0.friction},
          std::pair{e.contact_normal, e0.contact_normal}})
      worst_E = std::max(worst_E, relative(x, x0));
  }
  EXPECT_GT(contact_steps, 20);
  RecordProperty("impulses", std::to_string(worst_R));
  RecordProperty("velocities", std::to_string(worst_v));
  RecordProperty("energies", std::to_string(worst_E));
  std::cout << ranks << " ranks against 1: impulses " << worst_R
            << " (of the largest), boundary velocities " << worst_v
            << " m/s, energies " << worst_E << " (relative)\n";
  // The contact problem is the serial one, bit for bit (the contacts in
  // the serial order, W summed in the serial body order, solved whole on
  // every rank); the energies' body terms are sums over the ranks.
  EXPECT_EQ(worst_R, 0);
  EXPECT_EQ(worst_v, 0);
  EXPECT_LE(worst_E, 1e-12);
}
