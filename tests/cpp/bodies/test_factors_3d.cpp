// The factors of 3D bodies (BodyFactors with GeneralFactor): CHOLMOD's
// supernodal Cholesky, analyzed once and refactorized, solves the iteration
// matrix of a sheared nodal-pressure cylinder as Eigen's double-precision
// LDL^T does; many right-hand sides at once give the columns of one at a
// time; a matrix that is not positive definite is refused.
#include <Eigen/SparseCholesky>
#include <bodies/BodySet.h>
#include <compliance/body_factors.h>
#include <compliance/damping.h>
#include <compliance/general_factor.h>
#include <filesystem>
#include <gtest/gtest.h>
#include <map>
#include <material_registry.h>

using namespace softpack;

namespace
{
bodies::BodySet cylinder()
{
  const std::map<std::string, double> p = {{"shear_modulus", 0.15e6},
                                           {"lame_lambda", 1.35e6}};
  return bodies::BodySet(
      bodies::read_body_mesh(MPI_COMM_SELF,
                             std::filesystem::path(SOFTPACK_SOLID_MESHES) /
                                 "cylinder.xdmf"),
      forms::find_material("neo_hookean_nodal"), p, 1180);
}

/// Body 0's iteration matrix (h = 72 us, theta 0.55) under a strain that
/// varies, scaled by `mass_scale` on the mass
bodies::BodyMatrix iteration_matrix(bodies::BodySet& bodies,
                                    double mass_scale = 1)
{
  std::span<double> u = bodies.displacement();
  const auto x = bodies.reference_coordinates();
  for (std::size_t i = 0; i < u.size(); i += 3)
  {
    u[i] = 2 * x[i + 1] * x[i + 2];
    u[i + 1] = x[i] * x[i];
    u[i + 2] = -0.5 * x[i + 2] * x[i + 2];
  }
  std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
  bodies.tangent(K);
  const double h = 7.2e-5, th = 0.55;
  const bodies::BodyMatrix& M = bodies.consistent_mass()[0];
  bodies::BodyMatrix A = M;
  dynamics::combine({mass_scale, h * h * th * th}, M, K[0], A);
  return A;
}
} // namespace

TEST(BodyFactors3D, CholmodAnalyzedOnceSolvesAsEigenLDLT)
{
  bodies::BodySet bodies = cylinder();
  ASSERT_EQ(bodies.dim(), 3);
  const bodies::BodyMatrix A = iteration_matrix(bodies);
  const Eigen::SimplicialLDLT<bodies::BodyMatrix> reference(A);
  ASSERT_EQ(reference.info(), Eigen::Success);
  for (const std::string kind : {"cholmod", "simplicial"})
  {
    std::unique_ptr<dynamics::GeneralFactor> f =
        dynamics::make_general_factor(kind);
    f->analyze(bodies.consistent_mass()[0]);
    // Factorized twice on one analysis: the second gives the same answer.
    ASSERT_TRUE(f->factorize(bodies.consistent_mass()[0])) << kind;
    ASSERT_TRUE(f->factorize(A)) << kind;
    const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(A.rows(), -1, 2);
    const Eigen::VectorXd x = f->solve(y), x_ref = reference.solve(y);
    EXPECT_LT((x - x_ref).norm() / x_ref.norm(), 1e-12) << kind;
  }
}

TEST(BodyFactors3D, BlockSolvesGiveTheColumnsOfSingleSolves)
{
  bodies::BodySet bodies = cylinder();
  const bodies::BodyMatrix A = iteration_matrix(bodies);
  dynamics::BodyFactors factors(bodies, bodies.consistent_mass());
  ASSERT_TRUE(factors.solves_blocks());
  ASSERT_TRUE(
      factors.factorize([&](int, bodies::BodyMatrix& values) { values = A; }));
  const int n = factors.rows(0), m = 7;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, m);
  for (int j = 0; j < m; ++j)
    E((j * 37) % n, j) = 1;
  const Eigen::MatrixXd X = factors.solve(0, E);
  for (int j = 0; j < m; ++j)
  {
    const Eigen::VectorXd e = E.col(j), x = factors.solve(0, e);
    EXPECT_LT((X.col(j) - x).norm(), 1e-12 * x.norm()) << "column " << j;
    EXPECT_LT((A.selfadjointView<Eigen::Lower>() * x - e).norm(), 1e-9)
        << "column " << j;
  }
}

TEST(BodyFactors3D, RefusesAMatrixThatIsNotPositiveDefinite)
{
  bodies::BodySet bodies = cylinder();
  const bodies::BodyMatrix A = iteration_matrix(bodies, -1);
  dynamics::BodyFactors factors(bodies, bodies.consistent_mass());
  EXPECT_FALSE(
      factors.factorize([&](int, bodies::BodyMatrix& values) { values = A; }));
}
