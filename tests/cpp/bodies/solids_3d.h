#pragma once
// The test solids of tests/cpp/bodies (issue 40 item 1): gmsh meshes of a
// sphere (D 20 mm) and a finite cylinder (D 20 mm, H 15 mm, conforming to
// the planes x = 0 and y = 0) written by `python3 -m softpack.scene.solids`
// (the ctest fixture bodies3d.meshes), read as BodySets; the 3D
// compressible neo-Hookean law in closed form,
//   Psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
//   P = mu (F - F^-T) + lambda ln J F^-T;
// and the meshes' geometry (a radius they contain, a plane face's area).
#include <array>
#include <bodies/BodySet.h>
#include <cmath>
#include <filesystem>
#include <map>
#include <material_registry.h>
#include <span>
#include <string>

namespace softpack::test_solids
{
inline constexpr double mu = 0.15e6, lambda = 9 * mu, rho = 1180;
inline constexpr double D = 0.02, H = 0.015;
using Matrix = std::array<std::array<double, 3>, 3>;

inline std::filesystem::path mesh_file(const std::string& name)
{
  return std::filesystem::path(SOFTPACK_SOLID_MESHES) / (name + ".xdmf");
}

inline bodies::BodySet solid(const std::string& name,
                             const std::string& law = "neo_hookean")
{
  std::map<std::string, double> p = {{"shear_modulus", mu},
                                     {"lame_lambda", lambda}};
  return bodies::BodySet(bodies::read_body_mesh(MPI_COMM_SELF, mesh_file(name)),
                         forms::find_material(law), p, rho);
}

/// u = A X + t at every node
inline void set_affine(bodies::BodySet& bodies, const Matrix& A,
                       std::array<double, 3> t = {0, 0, 0})
{
  std::span<const double> X = bodies.reference_coordinates();
  std::span<double> u = bodies.displacement();
  for (std::size_t n = 0; n < X.size() / 3; ++n)
    for (int i = 0; i < 3; ++i)
      u[3 * n + i] = t[i] + A[i][0] * X[3 * n] + A[i][1] * X[3 * n + 1] +
                     A[i][2] * X[3 * n + 2];
}

inline double det(const Matrix& F)
{
  return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
         F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
         F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
}

/// F^-T (cofactor over determinant)
inline Matrix inverse_transpose(const Matrix& F)
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

inline double psi(const Matrix& F)
{
  double trC = 0;
  for (const auto& row : F)
    for (double f : row)
      trC += f * f;
  const double lnJ = std::log(det(F));
  return mu / 2 * (trC - 3) - mu * lnJ + lambda / 2 * lnJ * lnJ;
}

inline Matrix first_piola(const Matrix& F)
{
  const Matrix G = inverse_transpose(F);
  const double lnJ = std::log(det(F));
  Matrix P;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      P[i][j] = mu * (F[i][j] - G[i][j]) + lambda * lnJ * G[i][j];
  return P;
}

inline Matrix minus_identity(Matrix F)
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
inline double inner_radius(const bodies::BodySet& bodies, bool sphere)
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
inline double face_area(const bodies::BodySet& bodies, double height)
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

} // namespace softpack::test_solids
