// The block-sparse Delassus operator: builder, compressed rows, products;
// problem validation.

#include "DelassusMatrix.h"
#include "helpers.h"
#include "problem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
Eigen::Matrix2d block(double a, double b, double c, double d)
{
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m;
}
} // namespace

TEST(Delassus, BuilderSumsSortsAndSeparatesTheDiagonal)
{
  DelassusMatrix W(3);
  W.add_block(0, 2, block(1, 2, 3, 4));
  W.add_block(0, 0, block(5, 0, 0, 5));
  W.add_block(0, 1, block(0, 1, 0, 0));
  W.add_block(0, 2, block(1, 1, 1, 1)); // same pair through a second body
  W.add_block(0, 0, block(1, 0, 0, 1));
  W.add_block(2, 0, block(1, 3, 2, 4));
  W.add_block(1, 1, Eigen::Matrix2d::Identity());
  W.add_block(2, 2, Eigen::Matrix2d::Identity());
  EXPECT_FALSE(W.finalized());
  W.finalize();
  ASSERT_TRUE(W.finalized());
  EXPECT_EQ(W.num_contacts(), 3u);
  EXPECT_EQ(W.num_offdiagonal_blocks(), 3u);
  EXPECT_EQ(W.diagonal(0), block(6, 0, 0, 6));

  const auto cols = W.row_columns(0);
  ASSERT_EQ(cols.size(), 2u);
  EXPECT_EQ(cols[0], 1);
  EXPECT_EQ(cols[1], 2);
  EXPECT_EQ(W.row_blocks(0)[1], block(2, 3, 4, 5));
  EXPECT_TRUE(W.row_columns(1).empty());
  EXPECT_EQ(W.row_columns(2).size(), 1u);
}

TEST(Delassus, ProductMatchesDenseMatrix)
{
  const int nc = 7;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  std::srand(3);
  // a chain of contacts: a couples with a - 1 and a + 1
  for (int a = 0; a < nc; ++a)
    for (int b = std::max(0, a - 1); b <= std::min(nc - 1, a + 1); ++b)
      dense.block<2, 2>(2 * a, 2 * b) = Eigen::Matrix2d::Random();
  const Eigen::VectorXd r = Eigen::VectorXd::Random(2 * nc);
  const Eigen::VectorXd q = Eigen::VectorXd::Random(2 * nc);
  FrictionContactProblem2D p =
      make_problem(dense, q, std::vector<double>(nc, 0.3));
  EXPECT_EQ(p.W.num_offdiagonal_blocks(), 2u * (nc - 1));

  std::vector<double> u(q.data(), q.data() + q.size());
  p.W.multiply_add({r.data(), static_cast<std::size_t>(r.size())}, u);
  const Eigen::VectorXd expected = dense * r + q;
  for (int k = 0; k < 2 * nc; ++k)
    EXPECT_NEAR(u[k], expected[k], 1e-14);
  EXPECT_TRUE(to_dense(p.W).isApprox(dense, 0.0));
}

TEST(Delassus, RejectsOutOfRangeAndLateBlocks)
{
  DelassusMatrix W(2);
  EXPECT_THROW(W.add_block(2, 0, Eigen::Matrix2d::Identity()),
               std::out_of_range);
  W.add_block(0, 0, Eigen::Matrix2d::Identity());
  W.finalize();
  EXPECT_THROW(W.add_block(0, 0, Eigen::Matrix2d::Identity()),
               std::logic_error);
}

TEST(Delassus, RenumberedIsThePermutedOperatorWithTheSameRowSums)
{
  const int nc = 9;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  std::srand(5);
  for (int a = 0; a < nc; ++a) // each contact couples with three others
    for (int b : {a, (a + 2) % nc, (a + 3) % nc, (a + 7) % nc})
      dense.block<2, 2>(2 * a, 2 * b) = Eigen::Matrix2d::Random();
  const FrictionContactProblem2D p = make_problem(
      dense, Eigen::VectorXd::Zero(2 * nc), std::vector<double>(nc, 0.3));
  const std::vector<std::int32_t> order = {4, 0, 8, 2, 6, 1, 3, 5, 7};
  const DelassusMatrix R = p.W.renumbered(order);
  ASSERT_TRUE(R.finalized());
  EXPECT_EQ(R.num_offdiagonal_blocks(), p.W.num_offdiagonal_blocks());

  Eigen::MatrixXd permuted(2 * nc, 2 * nc);
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j)
      permuted.block<2, 2>(2 * i, 2 * j) =
          dense.block<2, 2>(2 * order[i], 2 * order[j]);
  EXPECT_TRUE(to_dense(R).isApprox(permuted, 0.0));

  // Each row sums its blocks in the original order: the same bits.
  const Eigen::VectorXd r = Eigen::VectorXd::Random(2 * nc);
  Eigen::VectorXd r_here(2 * nc);
  for (int i = 0; i < nc; ++i)
    r_here.segment<2>(2 * i) = r.segment<2>(2 * order[i]);
  for (int i = 0; i < nc; ++i)
  {
    const Eigen::Vector2d there = p.W.row_product(order[i], r.data());
    const Eigen::Vector2d here = R.row_product(i, r_here.data());
    EXPECT_EQ(here[0], there[0]) << i;
    EXPECT_EQ(here[1], there[1]) << i;
  }
}

TEST(Delassus, RenumberingNeedsAPermutationOfAFinalizedOperator)
{
  DelassusMatrix W(2);
  W.add_block(0, 0, Eigen::Matrix2d::Identity());
  W.add_block(1, 1, Eigen::Matrix2d::Identity());
  const std::vector<std::int32_t> swap = {1, 0}, twice = {1, 1},
                                  short_one = {0}, outside = {0, 2};
  EXPECT_THROW(W.renumbered(swap), std::invalid_argument); // not finalized
  W.finalize();
  EXPECT_NO_THROW(W.renumbered(swap));
  for (const auto* bad : {&twice, &short_one, &outside})
    EXPECT_THROW(W.renumbered(*bad), std::invalid_argument);
}

TEST(Validate, AcceptsAWellFormedProblem)
{
  FrictionContactProblem2D p = make_problem(
      Eigen::MatrixXd::Identity(4, 4), Eigen::VectorXd::Ones(4), {0.1, 0.0});
  EXPECT_NO_THROW(validate(p));
}

TEST(Validate, NamesWhatIsWrong)
{
  auto expect_message =
      [](const FrictionContactProblem2D& p, const std::string& part)
  {
    try
    {
      validate(p);
      ADD_FAILURE() << "no exception, expected: " << part;
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << e.what();
    }
  };
  const auto good = []
  {
    return make_problem(Eigen::MatrixXd::Identity(4, 4),
                        Eigen::VectorXd::Ones(4), {0.1, 0.2});
  };
  FrictionContactProblem2D p = good();
  p.friction[1] = -0.2;
  expect_message(p, "friction[1]");
  p = good();
  p.q.pop_back();
  expect_message(p, "q has 3 entries");
  p = good();
  p.q[2] = std::numeric_limits<double>::quiet_NaN();
  expect_message(p, "q[2] is not finite");
  p = good();
  p.friction.push_back(0.1);
  expect_message(p, "block rows");

  // a contact without its diagonal block
  p.W = DelassusMatrix(2);
  p.W.add_block(0, 0, Eigen::Matrix2d::Identity());
  p.W.add_block(1, 0, Eigen::Matrix2d::Identity());
  p.W.finalize();
  p.friction = {0.1, 0.1};
  expect_message(p, "contact 1 has W_nn");

  p.W = DelassusMatrix(2);
  expect_message(p, "not finalized");
}
