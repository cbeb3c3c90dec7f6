// Tetrahedral P1 bodies (issue 40 item 1) on the same BodySet code as the
// 2D triangles, on the test solids of solids_3d.h: the energy and stress of
// the 3D laws against the closed-form neo-Hookean law, their residual and
// tangent against central differences, a rigid rotation, the homogeneous
// uniaxial compression of the cylinder between frictionless plates, and the
// laws and readers that refuse 3D.
#include "solids_3d.h"

#include <bodies/static_newton.h>
#include <cmath>
#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace softpack;
using namespace softpack::test_solids;

namespace
{
/// The closed-form energy, nodal forces and volume of the sphere under a
/// homogeneous deformation in law `law`
void homogeneous_deformation_check(const std::string& law)
{
  bodies::BodySet bodies = solid("sphere", law);
  const Matrix F = {
      {{1.10, 0.20, -0.05}, {0.03, 0.85, 0.10}, {-0.08, 0.15, 1.20}}};
  set_affine(bodies, minus_identity(F), {0.01, -0.02, 0.03});
  const double V = bodies.body(0).reference_area;
  EXPECT_NEAR(bodies.strain_energy(), psi(F) * V, 1e-10 * psi(F) * V);

  // sum_n f_n (x) X_n = int P grad(X)^T dV = P V, and the interior nodes
  // carry no force (div P = 0)
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  std::span<const double> X = bodies.reference_coordinates();
  const Matrix P = first_piola(F);
  const double scale = mu * V;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      double sum = 0;
      for (std::size_t n = 0; n < X.size() / 3; ++n)
        sum += f[3 * n + i] * X[3 * n + j];
      EXPECT_NEAR(sum, P[i][j] * V, 1e-10 * scale) << i << j;
    }
  const bodies::Body& body = bodies.body(0);
  std::vector<char> boundary(body.nodes.size(), 0);
  for (std::int32_t k : body.boundary_nodes)
    boundary[k] = 1;
  const double length = std::cbrt(V);
  for (std::size_t k = 0; k < body.nodes.size(); ++k)
    if (!boundary[k])
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f[3 * body.nodes[k] + c], 0, 1e-10 * mu * length * length);
  // The deformed volume is det F V
  EXPECT_NEAR(bodies.body_current_area()[0], det(F) * V, 1e-13 * V);
}

/// Central differences of the energy and the internal force along a
/// random direction against the internal force and the tangent
void derivatives_check(const std::string& law)
{
  bodies::BodySet bodies = solid("cylinder", law);
  const std::size_t n = bodies.num_dofs();
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> noise(-1, 1);
  set_affine(bodies, {{{0.05, 0.1, 0}, {-0.02, -0.1, 0.03}, {0, 0.04, 0.08}}});
  std::span<double> u = bodies.displacement();
  for (double& v : u)
    v += 2e-4 * noise(gen); // 5 % of the 4 mm element size
  std::vector<double> w(n), f(n), fp(n), fm(n);
  for (double& v : w)
    v = noise(gen) * 1e-3;
  bodies.internal_force(f);
  std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
  bodies.tangent(K);
  const Eigen::Map<const Eigen::VectorXd> wv(w.data(), n);
  const Eigen::VectorXd Kw = bodies::symmetric_product(K[0], wv);

  const double h = 1e-4; // relative step along w
  auto shifted = [&](double s, std::vector<double>* force)
  {
    for (std::size_t i = 0; i < n; ++i)
      u[i] += s * w[i];
    const double e = bodies.strain_energy();
    if (force)
      bodies.internal_force(*force);
    for (std::size_t i = 0; i < n; ++i)
      u[i] -= s * w[i];
    return e;
  };
  const double dE = (shifted(h, &fp) - shifted(-h, &fm)) / (2 * h);
  const double fw = std::inner_product(f.begin(), f.end(), w.begin(), 0.0);
  EXPECT_NEAR(dE, fw, 1e-7 * std::abs(fw));
  double err = 0, norm = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double d = (fp[i] - fm[i]) / (2 * h);
    err = std::max(err, std::abs(d - Kw[i]));
    norm = std::max(norm, std::abs(Kw[i]));
  }
  EXPECT_LT(err, 1e-6 * norm);
}
} // namespace

constexpr const char* volumetric_laws[] = {"neo_hookean", "neo_hookean_nodal"};

TEST(Bodies3D, HomogeneousDeformationGivesTheClosedFormEnergyAndStress)
{
  for (const char* law : volumetric_laws)
  {
    SCOPED_TRACE(law);
    homogeneous_deformation_check(law);
  }
}

TEST(Bodies3D, ResidualAndTangentAreTheDerivativesOfEnergyAndResidual)
{
  for (const char* law : volumetric_laws)
  {
    SCOPED_TRACE(law);
    derivatives_check(law);
  }
}

TEST(Bodies3D, RigidRotationStoresNoEnergy)
{
  bodies::BodySet bodies = solid("sphere");
  // Rotation by 1 rad about (1, 2, 3)/sqrt(14) (Rodrigues), and a shift
  const double a = 1.0, k[3] = {1 / std::sqrt(14.0), 2 / std::sqrt(14.0),
                                3 / std::sqrt(14.0)};
  Matrix Q;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      const int e = (i == j) ? 1 : 0;
      double cross = 0; // [k]x_ij
      if ((i + 1) % 3 == j)
        cross = -k[(i + 2) % 3];
      else if ((j + 1) % 3 == i)
        cross = k[(j + 2) % 3];
      Q[i][j] = std::cos(a) * e + std::sin(a) * cross +
                (1 - std::cos(a)) * k[i] * k[j];
    }
  ASSERT_NEAR(det(Q), 1, 1e-14);
  set_affine(bodies, minus_identity(Q), {0.3, -0.1, 0.2});
  const double V = bodies.body(0).reference_area;
  EXPECT_LT(std::abs(bodies.strain_energy()), 1e-12 * mu * V);
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  const double length = std::cbrt(V);
  for (double v : f)
    EXPECT_LT(std::abs(v), 1e-10 * mu * length * length);
  EXPECT_NEAR(bodies.body_current_area()[0], V, 1e-12 * V);
}

TEST(Bodies3D, PlaneStrainOnlyLawsAreRefusedNamingThem)
{
  for (const char* law : {"viscoelastic_neo_hookean"})
  {
    try
    {
      const bodies::BodySet bodies = solid("sphere", law);
      ADD_FAILURE() << law << " accepted in 3D";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(law), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("plane strain only"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(Bodies3D, CylinderBetweenFrictionlessPlatesFollowsTheUniaxialClosedForm)
{
  // Compressed to s = 0.8 of its height between two frictionless plates
  // (u_z prescribed on the end faces, free in x, y) and held by rollers on
  // the planes x = 0 and y = 0: the homogeneous state F = diag(a, a, s),
  // free lateral faces: P11 = mu (a - 1/a) + lambda ln(a^2 s) / a = 0. The
  // mesh's lateral faces are vertical: the state is the discrete solution.
  bodies::BodySet bodies = solid("cylinder");
  std::span<const double> X = bodies.reference_coordinates();
  const std::size_t nodes = X.size() / 3;
  const double tol = 1e-9 * H, s = 0.8, R = D / 2;
  std::vector<std::int32_t> fixed, top;
  for (std::size_t n = 0; n < nodes; ++n)
  {
    const double x = X[3 * n], y = X[3 * n + 1], z = X[3 * n + 2];
    if (std::abs(z + H / 2) < tol || std::abs(z - H / 2) < tol)
      fixed.push_back(3 * n + 2);
    if (std::abs(z - H / 2) < tol)
      top.push_back(static_cast<std::int32_t>(n));
    if (std::abs(x) < tol)
      fixed.push_back(3 * n);
    if (std::abs(y) < tol)
      fixed.push_back(3 * n + 1);
  }
  ASSERT_GT(top.size(), 10u);
  const std::vector<double> f_ext(bodies.num_dofs(), 0.0);
  std::vector<double> values(fixed.size());
  constexpr int increments = 4;
  for (int k = 1; k <= increments; ++k)
  {
    const double shortening = (1 - s) * H * k / increments;
    for (std::size_t i = 0; i < fixed.size(); ++i)
      values[i] = fixed[i] % 3 == 2 && X[fixed[i]] > 0 ? -shortening : 0.0;
    const bodies::NewtonHistory h =
        bodies::solve_static_equilibrium(bodies, f_ext, fixed, values);
    ASSERT_TRUE(h.converged) << "increment " << k;
    RecordProperty("newton_iterations_" + std::to_string(k),
                   std::to_string(h.residual_norms.size() - 1));
  }
  // The closed form's lateral stretch (Newton on the scalar equation)
  double a = 1;
  for (int it = 0; it < 50; ++it)
    a -= (mu * (a * a - 1) + lambda * std::log(a * a * s)) /
         (2 * mu * a + 2 * lambda / a);
  std::span<const double> u = bodies.displacement();
  for (std::size_t n = 0; n < nodes; ++n)
  {
    const double expected[3] = {(a - 1) * X[3 * n], (a - 1) * X[3 * n + 1],
                                (s - 1) * (X[3 * n + 2] + H / 2)};
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(u[3 * n + c], expected[c], 1e-9 * R) << n << " " << c;
  }
  // The plate's force: P33 over the meshed end face, between P33 pi r^2
  // (r the meshed polygon's inner radius) and P33 pi R^2
  const double P33 = mu * (s - 1 / s) + lambda * std::log(a * a * s) / s;
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  double force = 0;
  for (std::int32_t n : top)
    force += f[3 * n + 2];
  const double area = face_area(bodies, H / 2);
  EXPECT_NEAR(force, P33 * area, 1e-9 * std::abs(P33) * area);
  RecordProperty("lateral_stretch", std::to_string(a));
  RecordProperty("force_over_P33_pi_R2",
                 std::to_string(force / (P33 * M_PI * R * R)));
  const double r = inner_radius(bodies, false);
  EXPECT_LT(std::abs(force), std::abs(P33) * M_PI * R * R);
  EXPECT_GT(std::abs(force), std::abs(P33) * M_PI * r * r);
  EXPECT_NEAR(bodies.body(0).reference_area, area * H, 1e-12 * area * H);
}

TEST(Bodies3D, TheDriversReaderRefusesATetrahedralMeshForPlaneStrainForms)
{
  // The time loop reads its mesh with the laws' 2D space
  // (run_simulation.cpp): a 3D mesh is refused naming the file
  const std::filesystem::path path = mesh_file("sphere");
  const forms::MaterialForms& law = forms::find_material("neo_hookean");
  try
  {
    bodies::read_body_geometry(path, law.function_space);
    ADD_FAILURE() << "a tetrahedral mesh read with 2D forms";
  }
  catch (const std::runtime_error& e)
  {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("tetrahedra"), std::string::npos) << what;
  }
  const bodies::BodyGeometry g = bodies::read_body_geometry(
      path, forms::in_dimension(law, 3).function_space);
  EXPECT_EQ(g.dim, 3);
  ASSERT_FALSE(g.cells.empty());
  EXPECT_EQ(g.cells[0].size(), 4);
  EXPECT_EQ(g.x.size(), 3u * g.num_nodes());
}
