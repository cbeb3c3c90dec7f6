// The integral of each body's Cauchy stress (bodies/stress_average.h): the
// law's compiled form and the internal-force identity against the analytic
// value of a homogeneous deformation, and against each other on a
// non-homogeneous one.
#include "mesh_fixtures.h"
#include <Eigen/Dense>
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <bodies/stress_average.h>
#include <cmath>
#include <gtest/gtest.h>
#include <material_defaults.h>
#include <material_registry.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180;
using Matrix = Eigen::Matrix2d;

/// A disk and a rectangle: two bodies, two shapes.
bodies::BodySet two_bodies(const std::string& law)
{
  return bodies::BodySet(
      test::bodies_mesh({test::disk(0, 0, 0.01, 4),
                         test::rectangle(0.03, -0.01, 0.02, 0.015, 4, 3)}),
      forms::find_material(law), bodies::plane_strain_parameters(mu), rho);
}

/// u = (F_b - I) X + t_b on body b (homogeneous: exact for P1)
void deform(bodies::BodySet& set, const std::vector<Matrix>& F)
{
  std::span<double> u = set.displacement();
  std::span<const double> X = set.reference_coordinates();
  for (int b = 0; b < set.num_bodies(); ++b)
    for (std::int32_t n : set.body(b).nodes)
    {
      const Eigen::Vector2d x(X[2 * n], X[2 * n + 1]);
      const Eigen::Vector2d d =
          (F[b] - Matrix::Identity()) * x + Eigen::Vector2d(0.002 * b, -0.001);
      u[2 * n] = d[0];
      u[2 * n + 1] = d[1];
    }
}

/// P F^T of the plane-strain laws (forms/materials/*.py), by hand
Matrix kirchhoff(const std::string& law, const Matrix& F)
{
  const double lambda = 2 * mu, J = F.determinant();
  if (law == "neo_hookean")
    return mu * (F * F.transpose() - Matrix::Identity()) +
           lambda * std::log(J) * Matrix::Identity();
  const Matrix E = 0.5 * (F.transpose() * F - Matrix::Identity());
  const Matrix S = lambda * E.trace() * Matrix::Identity() + 2 * mu * E;
  return F * S * F.transpose();
}

void expect_integrals(const std::vector<bodies::CauchyIntegral>& got,
                      const bodies::BodySet& set, const std::string& law,
                      const std::vector<Matrix>& F)
{
  for (int b = 0; b < set.num_bodies(); ++b)
  {
    const Matrix t = set.body(b).reference_area * kirchhoff(law, F[b]);
    const double scale = t.norm();
    EXPECT_NEAR(got[b][0], t(0, 0), 1e-12 * scale) << law << " body " << b;
    EXPECT_NEAR(got[b][1], t(1, 1), 1e-12 * scale) << law << " body " << b;
    EXPECT_NEAR(got[b][2], t(0, 1), 1e-12 * scale) << law << " body " << b;
    EXPECT_NEAR(got[b][3], t(1, 0), 1e-12 * scale) << law << " body " << b;
  }
}
} // namespace

TEST(StressAverage, HomogeneousDeformationGivesAreaTimesPFt)
{
  // compression with shear on one body, stretch with rotation on the other
  const double c = std::cos(0.3), s = std::sin(0.3);
  Matrix rotation;
  rotation << c, -s, s, c;
  Matrix F0, F1;
  F0 << 0.85, 0.12, -0.05, 0.9;
  F1 << 1.1, 0.0, 0.0, 0.95;
  const std::vector<Matrix> F = {F0, rotation * F1};
  for (const std::string law : {"neo_hookean", "saint_venant_kirchhoff"})
  {
    bodies::BodySet set = two_bodies(law);
    deform(set, F);
    expect_integrals(bodies::cauchy_integrals(set), set, law, F);
    bodies::CauchyIntegralForm form(set, forms::find_material(law),
                                    bodies::plane_strain_parameters(mu));
    expect_integrals(form.evaluate(), set, law, F);
  }
}

/// P F^T of Mooney-Rivlin and Gent in plane strain (their closed forms, as
/// forms/materials/mooney_rivlin.py and gent.py state them), lambda = 2 mu
Matrix kirchhoff_of(const std::string& law, const forms::ParameterValues& p,
                    const Matrix& F)
{
  const Matrix B = F * F.transpose(), I = Matrix::Identity();
  const double I1 = B.trace() + 1, lnJ = std::log(F.determinant());
  const double lambda = p.at("lame_lambda");
  if (law == "mooney_rivlin")
  {
    const double c10 = p.at("c10"), c01 = p.at("c01");
    return 2 * c10 * B + 2 * c01 * (I1 * B - B * B) +
           (lambda * lnJ - 2 * c10 - 4 * c01) * I;
  }
  const double m = p.at("shear_modulus"), jm = p.at("gent_jm");
  return m * jm / (jm - (I1 - 3)) * B - m * I + lambda * lnJ * I;
}

TEST(StressAverage, MooneyRivlinAndGentGiveTheirClosedForms)
{
  // the shipped default lambda (2 mu); a small Jm so that Gent's
  // stiffening shows (5-15 % from neo-Hookean at these strains)
  const std::map<std::string, forms::ParameterValues> given = {
      {"mooney_rivlin", {{"c10", 0.05e6}, {"c01", 0.025e6}}},
      {"gent", {{"shear_modulus", mu}, {"gent_jm", 2.5}}}};
  Matrix F0, F1;
  F0 << 0.85, 0.12, -0.05, 0.9;
  F1 << 1.1, 0.03, 0.0, 0.95;
  const std::vector<Matrix> F = {F0, F1};
  for (const auto& [law, values] : given)
  {
    const forms::ParameterValues p = forms::with_defaults(law, values);
    EXPECT_EQ(p.at("lame_lambda"), 2 * mu) << law;
    bodies::BodySet set(
        test::bodies_mesh({test::disk(0, 0, 0.01, 4),
                           test::rectangle(0.03, -0.01, 0.02, 0.015, 4, 3)}),
        forms::find_material(law), p, rho);
    deform(set, F);
    const std::vector<bodies::CauchyIntegral> got =
        bodies::cauchy_integrals(set);
    for (int b = 0; b < 2; ++b)
    {
      const Matrix t = set.body(b).reference_area * kirchhoff_of(law, p, F[b]);
      const double scale = t.norm();
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(got[b][k], t(k < 2 ? k : k - 2, k < 2 ? k : 3 - k),
                    1e-12 * scale)
            << law << " body " << b << " component " << k;
    }
  }
}

TEST(StressAverage, RigidMotionHasNoStress)
{
  const double c = std::cos(1.1), s = std::sin(1.1);
  Matrix rotation;
  rotation << c, -s, s, c;
  bodies::BodySet set = two_bodies("neo_hookean");
  deform(set, {rotation, Matrix::Identity()});
  for (const auto& body : bodies::cauchy_integrals(set))
    for (double v : body)
      EXPECT_NEAR(v, 0, 1e-9 * mu * 1e-4);
}

TEST(StressAverage, FormAndInternalForceAgreeOnAnInhomogeneousField)
{
  for (const std::string law : {"neo_hookean", "saint_venant_kirchhoff"})
  {
    bodies::BodySet set = two_bodies(law);
    std::span<double> u = set.displacement();
    std::span<const double> X = set.reference_coordinates();
    for (std::size_t n = 0; n < X.size() / 2; ++n)
    {
      const double x = X[2 * n], y = X[2 * n + 1];
      u[2 * n] = 0.1 * x * std::sin(90 * y) - 3 * x * x;
      u[2 * n + 1] = -0.08 * y + 2 * x * y;
    }
    const auto nodal = bodies::cauchy_integrals(set);
    const auto cells =
        bodies::CauchyIntegralForm(set, forms::find_material(law),
                                   bodies::plane_strain_parameters(mu))
            .evaluate();
    for (int b = 0; b < set.num_bodies(); ++b)
    {
      const double scale = std::hypot(cells[b][0], cells[b][1]);
      ASSERT_GT(scale, 0);
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(nodal[b][k], cells[b][k], 1e-11 * scale)
            << law << " body " << b << " component " << k;
    }
    // the Cauchy stress is symmetric: so is its integral
    for (int b = 0; b < set.num_bodies(); ++b)
      EXPECT_NEAR(cells[b][2], cells[b][3],
                  1e-11 * std::abs(cells[b][0]) + 1e-300);
  }
}

TEST(StressAverage, MissingParameterIsNamed)
{
  bodies::BodySet set = two_bodies("neo_hookean");
  EXPECT_THROW(
      {
        try
        {
          bodies::CauchyIntegralForm(set, forms::find_material("neo_hookean"),
                                     {{"shear_modulus", mu}});
        }
        catch (const std::invalid_argument& e)
        {
          EXPECT_NE(std::string(e.what()).find(
                        "material.parameters.lame_lambda: missing"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      std::invalid_argument);
}
