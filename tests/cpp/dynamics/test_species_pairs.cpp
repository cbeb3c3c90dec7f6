// Materials and friction per species (docs/materials.md): a body set of two
// materials equals the two single-material ones, and each contact takes the
// Coulomb coefficient of its pair of species (or species and wall).
#include "scheme_options.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dynamics/moreau_jean.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <random>

using namespace softpack;

namespace
{
constexpr double rho = 1180, width = 0.02, height = 0.005;

bodies::BodyMaterial material(const char* law, double mu, double density)
{
  return {&forms::find_material(law), bodies::plane_strain_parameters(mu),
          density, false, law};
}

/// Uniform body force per unit mass (gx, gy) on body b, lumped.
void add_body_force(const bodies::BodySet& set, int b, double gx, double gy,
                    std::vector<double>& f)
{
  const bodies::Body& body = set.body(b);
  const Eigen::VectorXd& m = set.lumped_mass()[b];
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
  {
    f[2 * body.nodes[k]] += m[2 * k] * gx;
    f[2 * body.nodes[k] + 1] += m[2 * k + 1] * gy;
  }
}

double mass(const bodies::BodySet& set, int b)
{
  return set.lumped_mass()[b].sum() / 2;
}

/// Mean x velocity of body b (momentum / mass).
double mean_vx(const bodies::BodySet& set, int b, std::span<const double> v)
{
  const Eigen::VectorXd& m = set.lumped_mass()[b];
  double p = 0;
  for (std::size_t k = 0; k < set.body(b).nodes.size(); ++k)
    p += m[2 * k] * v[2 * set.body(b).nodes[k]];
  return p / mass(set, b);
}

dynamics::MoreauJeanOptions options()
{
  dynamics::MoreauJeanOptions o = test::exact_options(1e-4, 0.01);
  o.damping.beta = 1e-4; // calms vibrations, leaves rigid motions free
  o.time.newton_tolerance = 1e-9;
  o.contact.nlgs_tolerance = 1e-10;
  return o;
}

const std::vector<dynamics::Wall> floor_wall = {
    {"floor", {0, 0}, {0, 1}, {0, 0}}};

/// Two neo-Hookean blocks, bodies 0 and 1 (species 0 and 1), on the floor.
bodies::BodySet two_blocks(const test::Triangulation& block0,
                           const test::Triangulation& block1)
{
  return bodies::BodySet(test::bodies_mesh({block0, block1}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), rho);
}

/// options() with a friction table of the two species and the floor: the
/// default 0.3 for every pair until set.
dynamics::MoreauJeanOptions options_with_pairs()
{
  dynamics::MoreauJeanOptions o = options();
  o.friction = dynamics::FrictionTable({0, 1}, 2, 1);
  return o;
}
} // namespace

TEST(BodyMaterials, TwoMaterialsEqualEachAlone)
{
  // A neo-Hookean disk and a stiffer, denser Saint Venant-Kirchhoff one in
  // one set: masses, strain energies and internal forces are those of each
  // body in a set of its own material.
  const auto disk_a = test::disk(0, 0, 0.01, 4),
             disk_b = test::disk(0.03, 0, 0.01, 4);
  const bodies::BodyMaterial a = material("neo_hookean", 0.15e6, rho),
                             b = material("saint_venant_kirchhoff", 1e6, 3000);
  bodies::BodySet both(test::bodies_mesh({disk_a, disk_b}), {a, b}, {0, 1});
  bodies::BodySet only_a(test::bodies_mesh({disk_a}), {a}, {0});
  bodies::BodySet only_b(test::bodies_mesh({disk_b}), {b}, {0});

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-5e-4, 5e-4);
  std::span<double> u = both.displacement();
  for (double& x : u)
    x = d(rng);
  // Bodies are numbered by the mesh, nodes by body: copy each body's part.
  for (auto [single, k] : {std::pair{&only_a, 0}, std::pair{&only_b, 1}})
  {
    const bodies::Body& whole = both.body(k);
    const bodies::Body& alone = single->body(0);
    ASSERT_EQ(whole.nodes.size(), alone.nodes.size());
    for (std::size_t n = 0; n < whole.nodes.size(); ++n)
      for (int c = 0; c < 2; ++c)
        single->displacement()[2 * alone.nodes[n] + c] =
            u[2 * whole.nodes[n] + c];
  }
  const std::vector<double> e = both.body_strain_energy();
  EXPECT_NEAR(e[0] / only_a.strain_energy(), 1.0, 1e-12);
  EXPECT_NEAR(e[1] / only_b.strain_energy(), 1.0, 1e-12);
  EXPECT_NEAR(both.strain_energy() / (e[0] + e[1]), 1.0, 1e-12);
  EXPECT_NEAR(mass(both, 0) / mass(only_a, 0), 1.0, 1e-12);
  EXPECT_NEAR(mass(both, 1) / mass(only_b, 0), 1.0, 1e-12);
  EXPECT_NEAR(mass(both, 1) / mass(both, 0), 3000 / rho, 1e-12);

  std::vector<double> f(both.num_dofs()), fa(only_a.num_dofs()),
      fb(only_b.num_dofs());
  both.internal_force(f);
  only_a.internal_force(fa);
  only_b.internal_force(fb);
  double diff = 0, scale = 0;
  for (auto [single, fs, k] :
       {std::tuple{&only_a, &fa, 0}, std::tuple{&only_b, &fb, 1}})
    for (std::size_t n = 0; n < both.body(k).nodes.size(); ++n)
      for (int c = 0; c < 2; ++c)
      {
        const double x = f[2 * both.body(k).nodes[n] + c];
        const double y = (*fs)[2 * single->body(0).nodes[n] + c];
        diff = std::max(diff, std::abs(x - y));
        scale = std::max(scale, std::abs(y));
      }
  EXPECT_LT(diff, 1e-12 * scale);
  // The tangent too: each body's block is its material's.
  std::vector<bodies::BodyMatrix> K = both.create_matrices(),
                                  Ka = only_a.create_matrices();
  both.tangent(K);
  only_a.tangent(Ka);
  EXPECT_LT((Eigen::MatrixXd(K[0]) - Eigen::MatrixXd(Ka[0])).norm(),
            1e-12 * Eigen::MatrixXd(Ka[0]).norm());
}

TEST(BodyMaterials, UnknownParameterNamesTheMaterial)
{
  bodies::BodyMaterial bad = material("neo_hookean", 0.15e6, rho);
  bad.parameters["shear_moduls"] = 1;
  bad.name = "materials[1]";
  try
  {
    bodies::BodySet set(test::bodies_mesh({test::disk(0, 0, 0.01, 2)}),
                        {material("neo_hookean", 0.15e6, rho), bad}, {1});
    FAIL() << "accepted an unknown parameter";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("materials[1].parameters."
                                         "shear_moduls: unknown parameter"),
              std::string::npos)
        << e.what();
  }
}

TEST(FrictionPairs, EachBlockSlidesWithItsSpeciesWallCoefficient)
{
  // Two blocks of species 0 and 1 on one floor, pushed by the same T per
  // unit weight: mu(0, floor) = 0.6 holds block 0, mu(1, floor) = 0.1 lets
  // block 1 slide at a = T/m - 0.1 g. The default (0.3) would hold both.
  bodies::BodySet set =
      two_blocks(test::rectangle(0, 0, width, height, 16, 4),
                 test::rectangle(0.05, 0, width, height, 16, 4));
  dynamics::MoreauJeanOptions o = options_with_pairs();
  o.friction.set(o.friction.species_party(0), o.friction.wall_party(0), 0.6);
  o.friction.set(o.friction.species_party(1), o.friction.wall_party(0), 0.1);
  const double g = 50, push = 0.2 * g;
  dynamics::MoreauJean scheme(set, floor_wall, o);
  std::vector<double> f(set.num_dofs(), 0.0);
  add_body_force(set, 0, push, -g, f);
  add_body_force(set, 1, push, -g, f);
  scheme.set_external_force(f);
  for (int s = 0; s < 200; ++s)
    ASSERT_TRUE(scheme.step().newton_converged);
  // Measured 2026-12-03 (this test): block 0 at 1.1e-8 m/s, block 1's
  // acceleration 7.7e-3 off (1 % kept).
  EXPECT_LT(std::abs(mean_vx(set, 0, scheme.velocity())), 1.2e-7);
  const double a = push - 0.1 * g;
  EXPECT_NEAR(mean_vx(set, 1, scheme.velocity()) / (a * scheme.time()), 1.0,
              0.01);
}

TEST(FrictionPairs, BlockOnBlockSlidesWithTheSpeciesPairCoefficient)
{
  // Block 1 (species 1) lies on block 0 (species 0), which lies on the
  // floor; block 1 is pushed by 0.3 g per unit mass and slides on block 0.
  // Every contact between the two blocks transmits |R_t| = mu(0, 1) R_n
  // with the pair's 0.1 (the default is 0.3); every floor contact at most
  // mu(0, floor) R_n = 1.0 R_n.
  bodies::BodySet set =
      two_blocks(test::rectangle(0, 0, 2 * width, height, 24, 3),
                 test::rectangle(0.5 * width, height, width, height, 12, 3));
  dynamics::MoreauJeanOptions o = options_with_pairs();
  o.friction.set(o.friction.species_party(0), o.friction.wall_party(0), 1.0);
  o.friction.set(o.friction.species_party(0), o.friction.species_party(1), 0.1);
  const double g = 50;
  dynamics::MoreauJean scheme(set, floor_wall, o);
  std::vector<double> f(set.num_dofs(), 0.0);
  add_body_force(set, 0, 0, -g, f);
  add_body_force(set, 1, 0.3 * g, -g, f);
  scheme.set_external_force(f);
  double normal = 0, tangential = 0;
  for (int s = 0; s < 60; ++s)
  {
    ASSERT_TRUE(scheme.step().newton_converged);
    const auto& R = scheme.impulses();
    for (std::size_t a = 0; a < scheme.contacts().size(); ++a)
    {
      const dynamics::Contact& c = scheme.contacts()[a];
      const double mu = c.wall >= 0 ? 1.0 : 0.1;
      EXPECT_LE(std::abs(R[2 * a + 1]), mu * R[2 * a] * (1 + 1e-6) + 1e-15)
          << "step " << s << " contact " << a;
      if (s >= 30 && c.wall < 0)
      {
        normal += R[2 * a];
        tangential += std::abs(R[2 * a + 1]);
      }
    }
  }
  // Block 1 slides: the pair's whole normal impulse carries mu(0, 1) of it.
  ASSERT_GT(normal, 0.0);
  EXPECT_NEAR(tangential / normal, 0.1, 1e-15); // measured 2.8e-17
  EXPECT_GT(mean_vx(set, 1, scheme.velocity()), 0.0);
}
