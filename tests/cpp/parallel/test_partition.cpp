// The recursive coordinate bisection of body centres (parallel/partition.h).
#include <algorithm>
#include <gtest/gtest.h>
#include <numeric>
#include <parallel/partition.h>
#include <stdexcept>

using softpack::parallel::partition_bodies;

namespace
{
/// Centres of an nx x ny grid of unit spacing, row by row.
std::vector<double> grid(int nx, int ny)
{
  std::vector<double> x;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      x.insert(x.end(), {double(i), double(j)});
  return x;
}
} // namespace

TEST(Partition, TwoPartsCutAcrossTheLongerSide)
{
  // 8 x 2 bodies: the cut is at x = 3.5, not at y.
  const std::vector<double> x = grid(8, 2);
  const std::vector<double> w(16, 1.0);
  const std::vector<int> part = partition_bodies(x, w, 2);
  for (int b = 0; b < 16; ++b)
    EXPECT_EQ(part[b], x[2 * b] < 4 ? 0 : 1) << "body " << b;
}

TEST(Partition, EveryPartGetsBodiesAndAFairShareOfTheWeight)
{
  const std::vector<double> x = grid(10, 7);
  std::vector<double> w(70);
  for (int b = 0; b < 70; ++b)
    w[b] = b % 3 == 0 ? 3.0 : 1.0; // two body sizes
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  for (int ranks : {1, 2, 3, 4, 7})
  {
    const std::vector<int> part = partition_bodies(x, w, ranks);
    std::vector<double> load(ranks, 0.0);
    for (int b = 0; b < 70; ++b)
    {
      ASSERT_GE(part[b], 0);
      ASSERT_LT(part[b], ranks);
      load[part[b]] += w[b];
    }
    for (int r = 0; r < ranks; ++r)
      EXPECT_NEAR(load[r], total / ranks, 3.0 * 2) // two bodies' worth
          << ranks << " ranks, part " << r;
  }
}

TEST(Partition, AsManyPartsAsBodiesGivesOneBodyEach)
{
  const std::vector<double> x = grid(5, 1);
  const std::vector<int> part =
      partition_bodies(x, std::vector<double>(5, 1.0), 5);
  std::vector<int> sorted = part;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(Partition, RanksOutsideOneToBodiesAreRefused)
{
  const std::vector<double> x = grid(3, 1);
  EXPECT_THROW(partition_bodies(x, std::vector<double>(3, 1.0), 0),
               std::invalid_argument);
  EXPECT_THROW(partition_bodies(x, std::vector<double>(3, 1.0), 4),
               std::invalid_argument);
}
