// The internal force assembled body by body on all cores is dolfinx's.
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <dolfinx/fem/assembler.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <random>

using namespace softpack;

class ParallelResidual : public ::testing::TestWithParam<const char*>
{
};

TEST_P(ParallelResidual, EqualsDolfinxAssemblerOnManyBodies)
{
  // 20 bodies: more than the 16 from which the loop is threaded.
  std::vector<test::Triangulation> parts;
  for (int i = 0; i < 20; ++i)
    parts.push_back(test::disk(0.03 * (i % 5), 0.03 * (i / 5), 0.01, 4));
  bodies::BodySet bodies(test::bodies_mesh(parts),
                         forms::find_material(GetParam()),
                         bodies::plane_strain_parameters(0.15e6), 1180);
  ASSERT_TRUE(bodies.parallel_residual());

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-1e-3, 1e-3);
  for (double& u : bodies.displacement())
    u = d(rng);
  std::vector<double> f(bodies.num_dofs()), reference(bodies.num_dofs(), 0.0);
  bodies.internal_force(f);
  dolfinx::fem::assemble_vector(std::span<double>(reference),
                                bodies.residual_form());
  double scale = 0, diff = 0;
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    scale = std::max(scale, std::abs(reference[i]));
    diff = std::max(diff, std::abs(f[i] - reference[i]));
  }
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(diff, 1e-13 * scale);
}

INSTANTIATE_TEST_SUITE_P(Materials, ParallelResidual,
                         ::testing::Values("neo_hookean",
                                           "saint_venant_kirchhoff"));
