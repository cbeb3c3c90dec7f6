// What `softpack fclib --describe` reports of a problem (problem_structure.h):
// its couplings by strength and its frictionless sets, on problems whose
// answers are known by hand.
#include "problem_structure.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace softpack::contact;

namespace
{
/// n 3D contacts, diagonal blocks 2 I, the listed pairs coupled by c I
FrictionContactProblem3D coupled(std::size_t n, std::vector<double> friction,
                                 const std::vector<std::pair<int, int>>& pairs,
                                 const std::vector<double>& c)
{
  FrictionContactProblem3D p;
  p.W = DelassusMatrix3D(n);
  for (std::size_t a = 0; a < n; ++a)
    p.W.add_block(a, a, 2.0 * Eigen::Matrix3d::Identity());
  for (std::size_t k = 0; k < pairs.size(); ++k)
  {
    p.W.add_block(pairs[k].first, pairs[k].second,
                  c[k] * Eigen::Matrix3d::Identity());
    p.W.add_block(pairs[k].second, pairs[k].first,
                  c[k] * Eigen::Matrix3d::Identity());
  }
  p.W.finalize();
  p.q.assign(3 * n, -1.0);
  p.friction = std::move(friction);
  return p;
}
} // namespace

TEST(ProblemStructure, CountsCouplingsByTheirStrength)
{
  // |W_ab| / sqrt(|W_aa| |W_bb|) = c / 2 for blocks c I and 2 I
  const FrictionContactProblem3D p = coupled(
      4, {0.3, 0.3, 0.3, 0.3}, {{0, 1}, {1, 2}, {2, 3}}, {2e-3, 2e-6, 2e-9});
  const ProblemStructure s = problem_structure(p);
  EXPECT_EQ(s.contacts, 4u);
  EXPECT_EQ(s.offdiagonal_blocks, 6u);
  ASSERT_EQ(s.coupling_thresholds.size(), 8u);
  // thresholds 1e-9 ... 1e-2: the 1e-9 pair at the first only (each pair
  // stored both ways)
  const std::vector<std::size_t> expected{6, 4, 4, 4, 2, 2, 2, 0};
  EXPECT_EQ(s.blocks_at_or_above, expected);
  EXPECT_EQ(s.frictionless, 0u);
  EXPECT_EQ(s.frictionless_sets, 0u);
}

TEST(ProblemStructure, FindsFrictionlessSetsAndTheirScaledEigenvalues)
{
  // 0-1-2 frictionless in a chain (scaled: tridiag(0.25, 1, 0.25),
  // eigenvalues 1 -+ 0.25 sqrt 2), 3 frictionless alone, 4 frictional and
  // coupled to 2 (not in the set)
  const FrictionContactProblem3D p =
      coupled(5, {0, 0, 0, 0, 0.3}, {{0, 1}, {1, 2}, {2, 4}}, {0.5, 0.5, 0.5});
  const ProblemStructure s = problem_structure(p);
  EXPECT_EQ(s.frictionless, 4u);
  EXPECT_EQ(s.frictionless_sets, 2u);
  EXPECT_EQ(s.smallest_set, 1u);
  EXPECT_EQ(s.largest_set, 3u);
  EXPECT_NEAR(s.scaled_eigenvalue_min, 1 - 0.25 * std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(s.scaled_eigenvalue_max, 1 + 0.25 * std::sqrt(2.0), 1e-14);
}
