// The bodies' factors (BodyFactors): copies of one mesh share one symbolic
// factorization whatever order dolfinx numbered their nodes in, and the
// single-precision values of L solve the iteration matrix to the accuracy
// their rounding allows, checked against Eigen's double-precision LDL^T.
#include <Eigen/SparseCholesky>
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <compliance/body_factors.h>
#include <compliance/damping.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
/// Three copies of one disk, another disk mesh and a rectangle.
bodies::BodySet five_bodies()
{
  return bodies::BodySet(
      test::bodies_mesh(
          {test::disk(0, 0, 0.01, 6), test::disk(0.03, 0, 0.01, 6),
           test::rectangle(0.06, -0.01, 0.02, 0.02, 5, 5),
           test::disk(0, 0.03, 0.01, 6), test::disk(0.03, 0.03, 0.015, 8)}),
      forms::find_material("neo_hookean"),
      bodies::plane_strain_parameters(0.15e6), 1180);
}

/// The iteration matrix of the paper case's step (h = 72 us, theta 0.55)
/// with each body sheared, so that the tangent differs from body to body.
struct IterationMatrices
{
  std::vector<bodies::BodyMatrix> K;
  dynamics::RayleighDamping::Combination kbar;
};

IterationMatrices iteration_matrices(bodies::BodySet& bodies)
{
  std::span<double> u = bodies.displacement();
  const auto x = bodies.reference_coordinates();
  for (std::size_t i = 0; i < u.size(); i += 2) // a strain that varies
  {
    u[i] = 2 * x[i + 1] * x[i + 1];
    u[i + 1] = x[i] * x[i];
  }
  IterationMatrices m{bodies.create_matrices(), {}};
  bodies.tangent(m.K);
  const double h = 7.2e-5, th = 0.55, alpha = 30, beta = 1e-5;
  m.kbar = {1 + h * th * alpha, h * th * beta + h * h * th * th};
  return m;
}
} // namespace

TEST(BodyFactors, CopiesOfOneMeshShareOneSymbolicFactorization)
{
  bodies::BodySet bodies = five_bodies();
  const std::vector<bodies::BodyMatrix>& M = bodies.consistent_mass();
  // In input order the copies have one pattern: disk(6) x 3, rectangle,
  // disk(8).
  dynamics::BodyFactors factors(bodies, M);
  EXPECT_EQ(factors.num_patterns(), 3);
  ASSERT_TRUE(
      factors.factorize([&](int b, bodies::BodyMatrix& A) { A = M[b]; }));
  EXPECT_EQ(factors.factor_entries(0), factors.factor_entries(1));
  EXPECT_EQ(factors.factor_entries(0), factors.factor_entries(3));
  EXPECT_NE(factors.factor_entries(0), factors.factor_entries(4));
}

TEST(BodyFactors, ACopyListedInAnotherNodeOrderHasItsOwnPattern)
{
  // The third disk's nodes listed backwards in the input: its matrix in
  // input order has another pattern (a fallback, not an error).
  test::Triangulation reversed = test::disk(0, 0.03, 0.01, 6);
  const std::int64_t n = static_cast<std::int64_t>(reversed.x.size() / 2);
  std::vector<double> x(reversed.x.size());
  for (std::int64_t i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c)
      x[2 * (n - 1 - i) + c] = reversed.x[2 * i + c];
  reversed.x = x;
  for (std::int64_t& v : reversed.cells)
    v = n - 1 - v;
  bodies::BodySet bodies(
      test::bodies_mesh(
          {test::disk(0, 0, 0.01, 6), test::disk(0.03, 0, 0.01, 6), reversed}),
      forms::find_material("neo_hookean"),
      bodies::plane_strain_parameters(0.15e6), 1180);
  const std::vector<bodies::BodyMatrix>& M = bodies.consistent_mass();
  dynamics::BodyFactors factors(bodies, M);
  EXPECT_EQ(factors.num_patterns(), 2);
  ASSERT_TRUE(
      factors.factorize([&](int b, bodies::BodyMatrix& A) { A = M[b]; }));
  const Eigen::VectorXd y = Eigen::VectorXd::Ones(M[2].rows());
  const Eigen::VectorXd x2 = factors.solve(2, y);
  EXPECT_LT((M[2].selfadjointView<Eigen::Lower>() * x2 - y).norm() / y.norm(),
            1e-6);
}

TEST(BodyFactors, SolvesAgreeWithDoublePrecisionLDLT)
{
  bodies::BodySet bodies = five_bodies();
  const IterationMatrices m = iteration_matrices(bodies);
  const std::vector<bodies::BodyMatrix>& M = bodies.consistent_mass();
  dynamics::BodyFactors factors(bodies, M);
  ASSERT_TRUE(
      factors.factorize([&](int b, bodies::BodyMatrix& A)
                        { dynamics::combine(m.kbar, M[b], m.K[b], A); }));
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    bodies::BodyMatrix A = M[b];
    dynamics::combine(m.kbar, M[b], m.K[b], A);
    const Eigen::SimplicialLDLT<bodies::BodyMatrix> reference(A);
    ASSERT_EQ(reference.info(), Eigen::Success);
    EXPECT_GT(factors.factor_entries(b), 0u);
    const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(A.rows(), -1, 2);
    const Eigen::VectorXd x = factors.solve(b, y);
    const Eigen::VectorXd x_ref = reference.solve(y);
    // float rounding (6e-8) of L's entries, amplified by the matrix's
    // conditioning (mass-dominated at this step: ~10-100); measured
    // 2026-12-03 over the five bodies at most 1.1e-8 (x), 1.2e-8 (residual),
    // 1.2e-8 (compliance column)
    EXPECT_LT((x - x_ref).norm() / x_ref.norm(), 1.2e-7) << "body " << b;
    EXPECT_LT((A.selfadjointView<Eigen::Lower>() * x - y).norm() / y.norm(),
              1.2e-7)
        << "body " << b;
    // A unit right-hand side (a compliance column) takes the sparse path.
    Eigen::VectorXd e = Eigen::VectorXd::Zero(A.rows());
    e[A.rows() / 2] = 1;
    const Eigen::VectorXd c = factors.solve(b, e), c_ref = reference.solve(e);
    EXPECT_LT((c - c_ref).norm() / c_ref.norm(), 1.2e-7) << "body " << b;
  }
}

TEST(BodyFactors, RefusesAMatrixThatIsNotPositiveDefinite)
{
  bodies::BodySet bodies = five_bodies();
  const IterationMatrices m = iteration_matrices(bodies);
  const std::vector<bodies::BodyMatrix>& M = bodies.consistent_mass();
  dynamics::BodyFactors factors(bodies, M);
  // M - 2 M on body 3 only: negative definite there.
  EXPECT_FALSE(factors.factorize(
      [&](int b, bodies::BodyMatrix& A)
      {
        const double a = b == 3 ? -1.0 : m.kbar.mass;
        dynamics::combine({a, m.kbar.stiffness}, M[b], m.K[b], A);
      }));
}
