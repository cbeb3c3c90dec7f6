// The factors of 3D bodies (BodyFactors with GeneralFactor): CHOLMOD's
// supernodal Cholesky, analyzed once and refactorized, solves the iteration
// matrix of a sheared nodal-pressure cylinder as Eigen's double-precision
// LDL^T does; many right-hand sides at once give the columns of one at a
// time; a matrix that is not positive definite is refused; the compliance
// columns of a body, solved a group of boundary slots at a time, depend on
// the factor alone.
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <bodies/BodySet.h>
#include <cmath>
#include <compliance/body_factors.h>
#include <compliance/damping.h>
#include <compliance/effective_stiffness.h>
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

namespace
{
/// Factorize the bodies' iteration matrices (h = 72 us, theta 0.55)
void factorize(dynamics::EffectiveStiffness& kbar,
               const bodies::BodySet& bodies)
{
  std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
  bodies.tangent(K);
  kbar.factorize(K, 1, 7.2e-5 * 7.2e-5 * 0.55 * 0.55);
}

/// Body 0's compliance columns at every boundary slot for the columns of
/// `slots`, prepared in the order given, one call per entry
std::vector<double> columns(const bodies::BodySet& bodies,
                            const std::vector<std::vector<int>>& calls,
                            const std::vector<int>& slots)
{
  dynamics::EffectiveStiffness kbar(bodies, false);
  factorize(kbar, bodies);
  for (const std::vector<int>& call : calls)
    kbar.prepare_columns(0, call);
  std::vector<double> values;
  const int n = static_cast<int>(bodies.body(0).boundary_nodes.size());
  for (const int j : slots)
    for (int i = 0; i < n; ++i)
    {
      const Eigen::Matrix3d block = kbar.boundary_block<3>(0, i, j);
      values.insert(values.end(), block.data(), block.data() + 9);
    }
  return values;
}
} // namespace

// A 3D body's compliance columns are solved a group of boundary slots at a
// time: the groups cover each slot once, and every column has the same bits
// whatever else was asked for before or with it (what a resumed run's
// columns, all new at once, rely on), within rounding of one solve per
// column. (How close together a group's slots lie is a matter of speed:
// ./softpack bench --solids3d.)
TEST(BodyFactors3D, ColumnsSolvedByGroupsDependOnTheFactorAlone)
{
  bodies::BodySet bodies = cylinder();
  iteration_matrix(bodies); // (for its strain: a tangent that varies)
  const dynamics::EffectiveStiffness kbar(bodies, false);
  const std::vector<std::int32_t>& boundary = bodies.body(0).boundary_nodes;
  const auto& groups = kbar.column_groups(0);
  std::vector<int> seen(boundary.size(), 0);
  for (const std::vector<std::int32_t>& group : groups)
  {
    EXPECT_LE(group.size(), 8u);
    for (const std::int32_t s : group)
      ++seen[s];
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1),
            static_cast<long>(boundary.size()));

  const int a = groups[0][0], b = groups[0].back(), c = groups[3][0];
  const std::vector<int> slots = {a, b, c};
  const std::vector<double> one_by_one =
      columns(bodies, {{a}, {b}, {c}}, slots);
  EXPECT_EQ(columns(bodies, {{c, b, a}}, slots), one_by_one);
  EXPECT_EQ(columns(bodies, {{c}, {a, b}}, slots), one_by_one);

  // Against one solve per column: block (r, c) of slot j at slot i is row
  // 3 i + r of column 3 j + c
  dynamics::EffectiveStiffness single(bodies, false);
  factorize(single, bodies);
  const std::size_t n = boundary.size();
  for (std::size_t k = 0; k < slots.size(); ++k)
    for (int col = 0; col < 3; ++col)
    {
      Eigen::VectorXd e =
          Eigen::VectorXd::Zero(3 * bodies.body(0).nodes.size());
      e[3 * boundary[slots[k]] + col] = 1;
      const Eigen::VectorXd x = single.solve(0, e);
      double diff = 0, scale = 0;
      for (std::size_t i = 0; i < n; ++i)
        for (int r = 0; r < 3; ++r)
        {
          const double v = one_by_one[9 * (k * n + i) + 3 * col + r];
          diff = std::max(diff, std::abs(v - x[3 * boundary[i] + r]));
          scale = std::max(scale, std::abs(x[3 * boundary[i] + r]));
        }
      EXPECT_LT(diff, 1e-12 * scale)
          << "slot " << slots[k] << " column " << col;
    }
}
