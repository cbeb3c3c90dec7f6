// The per-body forms assembled body by body on all cores (BodyAssembly)
// are dolfinx's: the strain energy, the internal force, the tangent and both
// masses, against
// dolfinx's assemblers over the same forms, to the rounding of the node
// coordinates (the body assembly reads those dolfinx tabulates for the
// DOFs, the assemblers the mesh geometry: they differ in the last bits).
#include <bodies/BodySet.h>
#include <bodies/body_materials.h>
#include <bodies/material_parameters.h>
#include <body.h>
#include <cmath>
#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <gtest/gtest.h>
#include <map>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <random>

using namespace softpack;

namespace
{
/// 20 bodies: more than the 16 from which the loops are threaded; a random
/// displacement (a fifth of the rings' spacing: no cell inverted), and the
/// mesh they were built from (the BodySet keeps none)
struct RandomBodies
{
  explicit RandomBodies(const forms::MaterialForms& law)
      : mesh(make_mesh()), bodies({mesh, cell_body, 20}, law,
                                  bodies::plane_strain_parameters(0.15e6), 1180)
  {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-5e-4, 5e-4);
    for (double& u : bodies.displacement())
      u = d(rng);
  }
  std::shared_ptr<dolfinx::mesh::Mesh> make_mesh()
  {
    std::vector<test::Triangulation> parts;
    for (int i = 0; i < 20; ++i)
      parts.push_back(test::disk(0.03 * (i % 5), 0.03 * (i / 5), 0.01, 4));
    bodies::BodyMesh m = test::bodies_mesh(parts);
    cell_body = m.cell_body;
    return m.mesh;
  }
  std::vector<int> cell_body;
  std::shared_ptr<dolfinx::mesh::Mesh> mesh;
  bodies::BodySet bodies;
};

/// A form of the material over the bodies' mesh, on the displacement's
/// space (`rank` times), as dolfinx makes it
dolfinx::fem::Form<double> dolfinx_form(const RandomBodies& set,
                                        const ufcx_form& form, int rank,
                                        const forms::MaterialForms& law)
{
  auto u = test::dolfinx_displacement(set.mesh, law, set.bodies);
  const std::vector<std::shared_ptr<const dolfinx::fem::FunctionSpace>> spaces(
      rank, u->function_space());
  return dolfinx::fem::create_form<double>(
      form, spaces, {{"u", u}},
      bodies::material_constants(
          {&law, bodies::plane_strain_parameters(0.15e6), 1180}),
      {}, set.mesh);
}

/// dolfinx's assembly of a bilinear form over the bodies' mesh, as
/// (global row DOF, global column DOF) -> value
std::map<std::pair<int, int>, double>
dolfinx_matrix(const RandomBodies& set, const ufcx_form& form,
               const forms::MaterialForms& law)
{
  const auto a = dolfinx_form(set, form, 2, law);
  std::map<std::pair<int, int>, double> A;
  auto add = [&](std::span<const std::int32_t> rows,
                 std::span<const std::int32_t> cols,
                 std::span<const double> values)
  {
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int ci = 0; ci < 2; ++ci)
        for (std::size_t j = 0; j < cols.size(); ++j)
          for (int cj = 0; cj < 2; ++cj)
            A[{2 * rows[i] + ci, 2 * cols[j] + cj}] +=
                values[(2 * i + ci) * 2 * cols.size() + 2 * j + cj];
    return 0;
  };
  dolfinx::fem::assemble_matrix(add, a, {});
  return A;
}

/// Relative difference allowed: a few roundings of the coordinates
constexpr double rounding = 1e-13;

/// Every stored entry of the per-body matrices equals dolfinx's global
/// entry to rounding; returns the number compared
int expect_same(const bodies::BodySet& bodies,
                const std::vector<bodies::BodyMatrix>& per_body,
                const std::map<std::pair<int, int>, double>& reference)
{
  double scale = 0;
  for (const auto& [key, value] : reference)
    scale = std::max(scale, std::abs(value));
  int compared = 0;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    const bodies::BodyMatrix& A = per_body[b];
    for (int col = 0; col < A.outerSize(); ++col)
      for (bodies::BodyMatrix::InnerIterator it(A, col); it; ++it)
      {
        const int gr = 2 * body.nodes[it.row() / 2] + it.row() % 2,
                  gc = 2 * body.nodes[col / 2] + col % 2;
        EXPECT_TRUE(std::isfinite(it.value()));
        EXPECT_NEAR(it.value(), reference.at({gr, gc}), rounding * scale)
            << "body " << b << " entry " << it.row() << ", " << col;
        ++compared;
      }
  }
  return compared;
}
} // namespace

class BodyAssembly : public ::testing::TestWithParam<const char*>
{
};

TEST_P(BodyAssembly, StrainEnergyIsDolfinxs)
{
  const forms::MaterialForms& law = forms::find_material(GetParam());
  const RandomBodies set(law);
  const double reference =
      dolfinx::fem::assemble_scalar(dolfinx_form(set, *law.energy, 0, law));
  ASSERT_GT(reference, 0.0);
  EXPECT_NEAR(set.bodies.strain_energy(), reference, rounding * reference);
  // Each cell's own: the body sums are the cells'
  const std::vector<double> cells = set.bodies.cell_strain_energy();
  const std::vector<double> per_body = set.bodies.body_strain_energy();
  for (int b = 0; b < set.bodies.num_bodies(); ++b)
  {
    double sum = 0;
    for (std::int32_t c : set.bodies.body(b).cells)
      sum += cells[c];
    EXPECT_GT(sum, 0.0);
    EXPECT_EQ(per_body[b], sum) << "body " << b;
  }
}

TEST_P(BodyAssembly, InternalForceIsDolfinxs)
{
  const forms::MaterialForms& law = forms::find_material(GetParam());
  const RandomBodies set(law);
  const bodies::BodySet& bodies = set.bodies;
  std::vector<double> f(bodies.num_dofs()), reference(bodies.num_dofs(), 0.0);
  bodies.internal_force(f);
  dolfinx::fem::assemble_vector(std::span<double>(reference),
                                dolfinx_form(set, *law.residual, 1, law));
  double scale = 0;
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    scale = std::max(scale, std::abs(reference[i]));
    ASSERT_TRUE(std::isfinite(f[i])) << "entry " << i;
  }
  ASSERT_GT(scale, 0.0);
  for (std::size_t i = 0; i < f.size(); ++i)
    EXPECT_NEAR(f[i], reference[i], rounding * scale) << "entry " << i;
}

TEST_P(BodyAssembly, TangentIsDolfinxs)
{
  const forms::MaterialForms& law = forms::find_material(GetParam());
  const RandomBodies set(law);
  std::vector<bodies::BodyMatrix> K = set.bodies.create_matrices();
  set.bodies.tangent(K);
  EXPECT_GT(expect_same(set.bodies, K, dolfinx_matrix(set, *law.tangent, law)),
            1000);
}

TEST_P(BodyAssembly, MassesAreDolfinxs)
{
  const forms::MaterialForms& law = forms::find_material(GetParam());
  const RandomBodies set(law);
  const bodies::BodySet& bodies = set.bodies;
  EXPECT_GT(expect_same(bodies, bodies.consistent_mass(),
                        dolfinx_matrix(set, *form_body_mass, law)),
            1000);
  const auto lumped = dolfinx_matrix(set, *form_body_lumped_mass, law);
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    for (int i = 0; i < body.num_dofs(); ++i)
    {
      const int g = 2 * body.nodes[i / 2] + i % 2;
      EXPECT_NEAR(bodies.lumped_mass()[b][i], lumped.at({g, g}),
                  rounding * lumped.at({g, g}));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Materials, BodyAssembly,
                         ::testing::Values("neo_hookean",
                                           "saint_venant_kirchhoff"));
