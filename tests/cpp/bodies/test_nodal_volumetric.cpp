// The averaged nodal pressure (bodies/nodal_volumetric.h, law
// neo_hookean_nodal): its internal force and tangent are the derivatives of
// its strain energy, and under a homogeneous deformation (J the same at
// every node) it is the paper's neo-Hookean law exactly.
#include "mesh_fixtures.h"
#include <Eigen/Dense>
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <bodies/stress_average.h>
#include <cmath>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <random>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180;

/// A disk and a rectangle in law `law`, lambda = 50 mu
bodies::BodySet two_bodies(const std::string& law)
{
  return bodies::BodySet(
      test::bodies_mesh({test::disk(0, 0, 0.01, 3),
                         test::rectangle(0.03, -0.01, 0.02, 0.015, 4, 3)}),
      forms::find_material(law),
      {{"shear_modulus", mu}, {"lame_lambda", 50 * mu}}, rho);
}

/// A random displacement of a few percent of the bodies' size
void perturb(bodies::BodySet& set, double size)
{
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> d(-size, size);
  for (double& u : set.displacement())
    u = d(gen);
}
} // namespace

TEST(NodalVolumetric, InternalForceAndTangentAreTheEnergysDerivatives)
{
  bodies::BodySet set = two_bodies("neo_hookean_nodal");
  perturb(set, 3e-4);
  std::vector<double> f(set.num_dofs());
  set.internal_force(f);
  std::vector<bodies::BodyMatrix> K = set.create_matrices();
  set.tangent(K);
  std::span<double> u = set.displacement();
  const double h = 1e-8,
               f_scale = Eigen::Map<Eigen::VectorXd>(f.data(), f.size())
                             .lpNorm<Eigen::Infinity>();
  double force_error = 0, tangent_error = 0, k_scale = 0;
  for (int b = 0; b < set.num_bodies(); ++b)
    k_scale = std::max(k_scale, Eigen::MatrixXd(K[b]).cwiseAbs().maxCoeff());
  for (int b = 0; b < set.num_bodies(); ++b)
  {
    const bodies::Body& body = set.body(b);
    // the lower triangle stored (BodySet.h): the whole matrix back
    const Eigen::MatrixXd lower = Eigen::MatrixXd(K[b]);
    const Eigen::MatrixXd Kb = lower + lower.transpose() -
                               Eigen::MatrixXd(lower.diagonal().asDiagonal());
    for (std::size_t i = 0; i < body.nodes.size(); i += 3)
      for (int d = 0; d < 2; ++d)
      {
        const std::size_t k = 2 * body.nodes[i] + d;
        const double u0 = u[k];
        std::vector<double> fp(f.size()), fm(f.size());
        u[k] = u0 + h;
        const double ep = set.strain_energy();
        set.internal_force(fp);
        u[k] = u0 - h;
        const double em = set.strain_energy();
        set.internal_force(fm);
        u[k] = u0;
        force_error =
            std::max(force_error, std::abs((ep - em) / (2 * h) - f[k]));
        for (std::size_t j = 0; j < body.nodes.size(); ++j)
          for (int e = 0; e < 2; ++e)
          {
            const std::size_t l = 2 * body.nodes[j] + e;
            tangent_error =
                std::max(tangent_error, std::abs((fp[l] - fm[l]) / (2 * h) -
                                                 Kb(2 * j + e, 2 * i + d)));
          }
      }
  }
  EXPECT_LT(force_error, 1e-5 * f_scale);
  EXPECT_LT(tangent_error, 1e-5 * k_scale);
}

TEST(NodalVolumetric, HomogeneousDeformationIsTheNeoHookeanLaw)
{
  // u = (F - I) X: J = det F at every node and in every triangle
  Eigen::Matrix2d F;
  F << 0.9, 0.1, -0.04, 1.05;
  std::vector<double> energy, force_norm;
  std::vector<bodies::CauchyIntegral> stress;
  for (const std::string law : {"neo_hookean_nodal", "neo_hookean"})
  {
    bodies::BodySet set = two_bodies(law);
    std::span<double> u = set.displacement();
    std::span<const double> X = set.reference_coordinates();
    for (std::size_t n = 0; n < u.size() / 2; ++n)
    {
      const Eigen::Vector2d x(X[2 * n], X[2 * n + 1]);
      const Eigen::Vector2d d = (F - Eigen::Matrix2d::Identity()) * x;
      u[2 * n] = d[0];
      u[2 * n + 1] = d[1];
    }
    energy.push_back(set.strain_energy());
    stress.push_back(bodies::cauchy_integrals(set)[1]);
  }
  EXPECT_NEAR(energy[0], energy[1], 1e-12 * energy[1]);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(stress[0][k], stress[1][k],
                1e-10 * std::abs(stress[1][0]) + 1e-10)
        << k;
}
