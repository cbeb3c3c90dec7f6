// Rigid bodies (docs/materials.md): three degrees of freedom each through
// the same contact operator and Delassus assembly as the soft bodies; their
// motion is exactly rigid and the energy accounts close.
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

bodies::BodyMaterial soft()
{
  return {&forms::find_material("neo_hookean"),
          bodies::plane_strain_parameters(mu), rho, false, "soft"};
}

bodies::BodyMaterial rigid(double density)
{
  return {&forms::find_material("neo_hookean"),
          bodies::plane_strain_parameters(mu), density, true, "rigid"};
}

/// Current position of local node i of body b.
Eigen::Vector2d position(const bodies::BodySet& set, int b, std::size_t i)
{
  const std::int32_t g = set.body(b).nodes[i];
  const auto X = set.reference_coordinates();
  const auto u = set.displacement();
  return {X[2 * g] + u[2 * g], X[2 * g + 1] + u[2 * g + 1]};
}

/// Largest relative change of the distance of every node of body b to
/// every other (reference against current).
double distance_change(const bodies::BodySet& set, int b)
{
  const auto X = set.reference_coordinates();
  const bodies::Body& body = set.body(b);
  double worst = 0;
  for (std::size_t i = 0; i < body.nodes.size(); ++i)
    for (std::size_t j = i + 1; j < body.nodes.size(); ++j)
    {
      const std::int32_t gi = body.nodes[i], gj = body.nodes[j];
      const double d0 =
          std::hypot(X[2 * gi] - X[2 * gj], X[2 * gi + 1] - X[2 * gj + 1]);
      const double d = (position(set, b, i) - position(set, b, j)).norm();
      worst = std::max(worst, std::abs(d - d0) / d0);
    }
  return worst;
}

/// Linear and angular momentum (about the origin) of body b, lumped mass.
Eigen::Vector3d momentum(const bodies::BodySet& set, int b,
                         std::span<const double> v)
{
  const Eigen::VectorXd& m = set.lumped_mass()[b];
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < set.body(b).nodes.size(); ++i)
  {
    const std::int32_t g = set.body(b).nodes[i];
    const Eigen::Vector2d x = position(set, b, i), vi(v[2 * g], v[2 * g + 1]);
    p.head<2>() += m[2 * i] * vi;
    p[2] += m[2 * i] * (x.x() * vi.y() - x.y() * vi.x());
  }
  return p;
}
} // namespace

TEST(RigidBodies, FreeRigidBodyKeepsItsMomentaAndShape)
{
  bodies::BodySet set(test::bodies_mesh({test::disk(0, 0, R, 4)}),
                      {rigid(2500)}, {0});
  dynamics::MoreauJeanOptions o = test::exact_options(2e-4, 1e-3);
  o.damping.alpha = 50; // acts on soft bodies only
  dynamics::MoreauJean scheme(set, {}, o);
  const auto X = set.reference_coordinates();
  std::vector<double> v(X.size());
  for (std::size_t i = 0; i < X.size() / 2; ++i)
  {
    v[2 * i] = 0.3 - 40 * X[2 * i + 1];
    v[2 * i + 1] = -0.1 + 40 * X[2 * i];
  }
  scheme.set_initial_velocity(v);
  const Eigen::Vector3d p0 = momentum(set, 0, v);
  const double kinetic0 = scheme.energy().kinetic;
  for (int s = 0; s < 200; ++s)
    ASSERT_TRUE(scheme.step().newton_converged);
  // 200 steps of 8e-3 rad: 1.6 rad of rotation, 12 mm of flight.
  const Eigen::Vector3d p = momentum(set, 0, scheme.velocity());
  EXPECT_LT((p.head<2>() - p0.head<2>()).norm(), 1e-12 * p0.head<2>().norm());
  EXPECT_NEAR(p[2] / p0[2], 1.0, 1e-12);
  EXPECT_LT(distance_change(set, 0), 1e-13);
  // The mass centre flew at its velocity, and the body turned by omega t.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < set.body(0).nodes.size(); ++i)
  {
    centre += set.lumped_mass()[0][2 * i] * position(set, 0, i);
    mass += set.lumped_mass()[0][2 * i];
  }
  centre /= mass;
  const double t = scheme.time();
  EXPECT_NEAR(centre.x(), 0.3 * t, 1e-14);
  EXPECT_NEAR(centre.y(), -0.1 * t, 1e-14);
  const std::size_t edge = set.body(0).boundary_nodes.front();
  const Eigen::Vector2d r0(X[2 * set.body(0).nodes[edge]],
                           X[2 * set.body(0).nodes[edge] + 1]);
  const Eigen::Vector2d r = position(set, 0, edge) - centre;
  EXPECT_NEAR(std::atan2(r0.x() * r.y() - r0.y() * r.x(), r0.dot(r)),
              std::remainder(40 * t, 2 * M_PI), 1e-12);
  const dynamics::EnergyBalance& e = scheme.energy();
  EXPECT_NEAR(e.kinetic / kinetic0, 1.0, 1e-12);
  EXPECT_LT(std::abs(e.strain), 1e-12 * kinetic0);
  EXPECT_EQ(e.damping, 0.0);
}

TEST(RigidBodies, RigidDiskBetweenSoftDisksMovesRigidlyAndTheBalanceCloses)
{
  // Soft - rigid - soft disks in a row between a fixed wall and a piston.
  const double gap = 2e-5;
  bodies::BodySet set(
      test::bodies_mesh({test::disk(R + gap, R, R, 4),
                         test::disk(3 * R + 2 * gap, R + 0.002, R, 4),
                         test::disk(5 * R + 3 * gap, R, R, 4)}),
      {soft(), rigid(rho)}, {0, 1, 0});
  const double L = 6 * R + 4 * gap, speed = 0.05;
  std::vector<dynamics::Wall> walls = {{"left", {0, 0}, {1, 0}, {0, 0}},
                                       {"right", {L, 0}, {-1, 0}, {-speed, 0}},
                                       {"bottom", {0, 0}, {0, 1}, {0, 0}}};
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, speed);
  o.time.newton_tolerance = 1e-9;
  o.contact.nlgs_tolerance = 1e-10;
  dynamics::MoreauJean scheme(set, walls, o);
  int converged = 0, steps = 150, rigid_contacts = 0;
  for (int s = 0; s < steps; ++s)
  {
    const dynamics::StepReport r = scheme.step();
    converged += r.newton_converged && r.nlgs_converged;
    for (const dynamics::Contact& c : scheme.contacts())
      rigid_contacts += (c.candidate_body == 1 || c.antagonist_body == 1);
  }
  EXPECT_EQ(converged, steps);
  ASSERT_GT(rigid_contacts, 0);
  // The piston moved 0.75 mm: the soft disks deformed, the rigid one not.
  // Measured 2026-12-03 (this test): distances 2.4e-14, rigid strain energy
  // 2.1e-13 of the work, energy residual 7.6e-5 of it.
  EXPECT_LT(distance_change(set, 1), 3e-13);
  const std::vector<double> strain = set.body_strain_energy();
  const dynamics::EnergyBalance& e = scheme.energy();
  EXPECT_GT(e.wall_work, 0.0);
  EXPECT_GT(strain[0], 0.1 * e.wall_work);
  EXPECT_LT(std::abs(strain[1]), 2e-12 * e.wall_work);
  EXPECT_LT(std::abs(e.residual()), 8e-4 * e.wall_work)
      << "residual " << e.residual() << " of wall work " << e.wall_work;
}

TEST(RigidBodies, EveryRankKeepsTheRigidBodiesMasses)
{
  // RigidBodies reads every rigid body's mass when a scheme is made, on
  // every rank: a rank that owns only soft bodies keeps the rigid ones'.
  bodies::BodySet set(
      test::bodies_mesh({test::disk(0, 0, R, 4), test::disk(3 * R, 0, R, 4)}),
      {soft(), rigid(rho)}, {0, 1});
  EXPECT_EQ(set.kept_masses(), (std::vector<char>{1, 1}));
  const Eigen::Index entries = set.consistent_mass()[1].nonZeros();
  set.set_local({0});
  EXPECT_EQ(set.kept_masses(), (std::vector<char>{1, 1}));
  EXPECT_EQ(set.consistent_mass()[1].nonZeros(), entries);
  EXPECT_GT(entries, 0);
  set.set_local({1});
  EXPECT_EQ(set.kept_masses(), (std::vector<char>{0, 1}));
  EXPECT_EQ(set.consistent_mass()[0].nonZeros(), 0);
}
