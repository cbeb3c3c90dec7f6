// Tetrahedral P1 bodies (issue 40 item 1) on the same BodySet code as the
// 2D triangles, on gmsh meshes of a sphere (D 20 mm) and a finite cylinder
// (D 20 mm, H 15 mm, conforming to the planes x = 0 and y = 0) written by
// `python3 -m softpack.scene.solids` (the ctest fixture bodies3d.meshes).
// References: the 3D compressible neo-Hookean law in closed form,
//   Psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
//   P = mu (F - F^-T) + lambda ln J F^-T,
// the geometry of the meshes, central differences, and the homogeneous
// uniaxial compression between frictionless plates.
#include <bodies/BodySet.h>
#include <bodies/static_newton.h>
#include <cmath>
#include <filesystem>
#include <gtest/gtest.h>
#include <map>
#include <material_registry.h>
#include <numeric>
#include <random>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, lambda = 9 * mu, rho = 1180;
constexpr double D = 0.02, H = 0.015;
using Matrix = std::array<std::array<double, 3>, 3>;

std::filesystem::path mesh_file(const std::string& name)
{
  return std::filesystem::path(SOFTPACK_SOLID_MESHES) / (name + ".xdmf");
}

bodies::BodySet solid(const std::string& name,
                      const std::string& law = "neo_hookean")
{
  std::map<std::string, double> p = {{"shear_modulus", mu},
                                     {"lame_lambda", lambda}};
  return bodies::BodySet(bodies::read_body_mesh(MPI_COMM_SELF, mesh_file(name)),
                         forms::find_material(law), p, rho);
}

/// u = A X + t at every node
void set_affine(bodies::BodySet& bodies, const Matrix& A,
                std::array<double, 3> t = {0, 0, 0})
{
  std::span<const double> X = bodies.reference_coordinates();
  std::span<double> u = bodies.displacement();
  for (std::size_t n = 0; n < X.size() / 3; ++n)
    for (int i = 0; i < 3; ++i)
      u[3 * n + i] = t[i] + A[i][0] * X[3 * n] + A[i][1] * X[3 * n + 1] +
                     A[i][2] * X[3 * n + 2];
}

double det(const Matrix& F)
{
  return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
         F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
         F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
}

/// F^-T (cofactor over determinant)
Matrix inverse_transpose(const Matrix& F)
{
  Matrix C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3,
                j2 = (j + 2) % 3;
      C[i][j] = (F[i1][j1] * F[i2][j2] - F[i1][j2] * F[i2][j1]) / det(F);
    }
  return C;
}

double psi(const Matrix& F)
{
  double trC = 0;
  for (const auto& row : F)
    for (double f : row)
      trC += f * f;
  const double lnJ = std::log(det(F));
  return mu / 2 * (trC - 3) - mu * lnJ + lambda / 2 * lnJ * lnJ;
}

Matrix first_piola(const Matrix& F)
{
  const Matrix G = inverse_transpose(F);
  const double lnJ = std::log(det(F));
  Matrix P;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      P[i][j] = mu * (F[i][j] - G[i][j]) + lambda * lnJ * G[i][j];
  return P;
}

Matrix minus_identity(Matrix F)
{
  for (int i = 0; i < 3; ++i)
    F[i][i] -= 1;
  return F;
}

/// A radius the meshed solid contains: each curved boundary face (its
/// nodes on the exact surface) is no nearer the centre than its plane
/// (sphere), or than its projection's chords (cylinder: R cos(phi/2), phi
/// the angle of two of its nodes about the axis). The meshed volume lies
/// between the solid of that radius and the exact one.
double inner_radius(const bodies::BodySet& bodies, bool sphere)
{
  const bodies::Body& body = bodies.body(0);
  std::span<const double> X = bodies.reference_coordinates();
  const double R = D / 2;
  double least = R;
  for (const auto& face : body.boundary_faces)
  {
    std::array<std::array<double, 3>, 3> p;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        p[k][c] = sphere || c < 2 ? X[3 * body.nodes[face[k]] + c] : 0.0;
    bool curved = true;
    for (const auto& q : p)
      curved &= std::abs(std::hypot(q[0], q[1], q[2]) - R) < 1e-9 * R;
    if (!curved)
      continue;
    if (sphere)
    {
      double n[3], e1[3], e2[3];
      for (int c = 0; c < 3; ++c)
      {
        e1[c] = p[1][c] - p[0][c];
        e2[c] = p[2][c] - p[0][c];
      }
      for (int c = 0; c < 3; ++c)
        n[c] = e1[(c + 1) % 3] * e2[(c + 2) % 3] -
               e1[(c + 2) % 3] * e2[(c + 1) % 3];
      least = std::min(
          least, std::abs(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]) /
                     std::hypot(n[0], n[1], n[2]));
      continue;
    }
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
      {
        const double c = (p[a][0] * p[b][0] + p[a][1] * p[b][1]) / (R * R);
        least = std::min(least, R * std::cos(std::acos(std::min(c, 1.0)) / 2));
      }
  }
  return least;
}
/// The area of the boundary faces of body 0 in the plane z = height
double face_area(const bodies::BodySet& bodies, double height)
{
  const bodies::Body& body = bodies.body(0);
  std::span<const double> X = bodies.reference_coordinates();
  double area = 0;
  for (const auto& face : body.boundary_faces)
  {
    double p[3][3];
    bool in_plane = true;
    for (int k = 0; k < 3; ++k)
    {
      for (int c = 0; c < 3; ++c)
        p[k][c] = X[3 * body.nodes[face[k]] + c];
      in_plane &= std::abs(p[k][2] - height) < 1e-9 * H;
    }
    if (in_plane)
      area += 0.5 * std::abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                             (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
  }
  return area;
}
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

TEST(Bodies3D, MassIsDensityTimesTheMeshedVolume)
{
  for (const std::string name : {"sphere", "cylinder"})
  {
    const bool sphere = name == "sphere";
    const bodies::BodySet bodies = solid(name);
    ASSERT_EQ(bodies.dim(), 3);
    ASSERT_EQ(bodies.num_bodies(), 1);
    const bodies::Body& body = bodies.body(0);
    EXPECT_EQ(body.num_dofs(), 3 * int(body.nodes.size()));
    const double V = body.reference_area;
    const std::vector<double> cells = bodies.cell_reference_area();
    // The sum of the tetrahedra against the boundary's divergence theorem
    EXPECT_NEAR(std::accumulate(cells.begin(), cells.end(), 0.0), V, 1e-13 * V);
    EXPECT_NEAR(bodies.body_current_area()[0], V, 1e-13 * V);
    // Against the analytic volume, to the mesh's own error
    const double R = D / 2, r = inner_radius(bodies, sphere);
    const double exact = sphere ? M_PI / 6 * D * D * D : M_PI * R * R * H;
    const double lower = exact * std::pow(r / R, sphere ? 3 : 2);
    EXPECT_LT(V, exact);
    EXPECT_GT(V, lower);
    EXPECT_LT((exact - V) / exact, 0.1); // the meshes are coarse: 4 mm
    RecordProperty(name + "_volume_over_exact", std::to_string(V / exact));
    RecordProperty(name + "_inscribed_over_exact",
                   std::to_string(lower / exact));
    // Lumped: rho V in each direction; consistent: the sum of one
    // direction's block is rho V
    const Eigen::VectorXd& m = bodies.lumped_mass()[0];
    const bodies::BodyMatrix& M = bodies.consistent_mass()[0];
    for (int c = 0; c < 3; ++c)
    {
      double lumped = 0;
      for (int k = c; k < m.size(); k += 3)
      {
        EXPECT_GT(m[k], 0);
        lumped += m[k];
      }
      EXPECT_NEAR(lumped, rho * V, 1e-12 * rho * V);
      Eigen::VectorXd e = Eigen::VectorXd::Zero(m.size());
      for (int k = c; k < m.size(); k += 3)
        e[k] = 1;
      EXPECT_NEAR(e.dot(bodies::symmetric_product(M, e)), rho * V,
                  1e-12 * rho * V);
    }
  }
}

/// neo_hookean_nodal (the averaged nodal pressure) is neo_hookean under a
/// homogeneous deformation (J the same at every node) and has the same
/// derivatives' checks
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

TEST(Bodies3D, BoundaryFacesAreAClosedSurfaceOrientedOutward)
{
  // What the 3D detection's BoundarySurface takes: every edge in exactly
  // two faces, once each way, and (b - a) x (c - a) outward (the sphere is
  // convex: away from its centre)
  const bodies::BodySet bodies = solid("sphere");
  const bodies::Body& body = bodies.body(0);
  std::span<const double> X = bodies.reference_coordinates();
  std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
  for (const auto& f : body.boundary_faces)
  {
    for (int k = 0; k < 3; ++k)
      ++edges[{f[k], f[(k + 1) % 3]}];
    double p[3][3], n[3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        p[k][c] = X[3 * body.nodes[f[k]] + c];
    for (int c = 0; c < 3; ++c)
      n[c] = (p[1][(c + 1) % 3] - p[0][(c + 1) % 3]) *
                 (p[2][(c + 2) % 3] - p[0][(c + 2) % 3]) -
             (p[1][(c + 2) % 3] - p[0][(c + 2) % 3]) *
                 (p[2][(c + 1) % 3] - p[0][(c + 1) % 3]);
    EXPECT_GT(n[0] * (p[0][0] + p[1][0] + p[2][0]) +
                  n[1] * (p[0][1] + p[1][1] + p[2][1]) +
                  n[2] * (p[0][2] + p[1][2] + p[2][2]),
              0);
  }
  for (const auto& [edge, count] : edges)
  {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
  // Euler: a sphere's surface has V - E + F = 2
  const std::size_t V = body.boundary_nodes.size(), E = edges.size() / 2,
                    F = body.boundary_faces.size();
  EXPECT_EQ(V + F, E + 2);
}
