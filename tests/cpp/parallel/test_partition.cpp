// The recursive coordinate bisection of body centres (parallel/partition.h).
#include <algorithm>
#include <array>
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

TEST(Partition, ASplitHasDriftedWhenUnevenOrScatteredNotWhenClose)
{
  using softpack::parallel::split_has_drifted;
  // 8 x 2 grid, two parts by x; links between horizontal neighbours.
  const std::vector<double> x = grid(8, 2);
  std::vector<double> w(16, 1.0);
  const std::vector<int> fresh = partition_bodies(x, w, 2);
  std::vector<std::array<int, 2>> links;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i + 1 < 8; ++i)
      links.push_back({8 * j + i, 8 * j + i + 1});
  // The same split: nothing to do.
  EXPECT_FALSE(split_has_drifted(fresh, fresh, 2, w, links, 0.1));
  // One body (of 16) on the other side: 1/8 uneven, above 10 %.
  std::vector<int> shifted = fresh;
  shifted[3] = 1;
  EXPECT_TRUE(split_has_drifted(shifted, fresh, 2, w, links, 0.1));
  // ... but within a 20 % tolerance, and it cuts as many links (2).
  EXPECT_FALSE(split_has_drifted(shifted, fresh, 2, w, links, 0.2));
  // Even but scattered (alternate columns): 14 cut links against 2.
  std::vector<int> striped(16);
  for (int b = 0; b < 16; ++b)
    striped[b] = (b % 8) % 2;
  EXPECT_TRUE(split_has_drifted(striped, fresh, 2, w, links, 0.2));
  // Uneven (a heavy body) but the other split is no better: the same
  // split with the parts' names swapped.
  std::vector<double> heavy(16, 1.0);
  heavy[0] = 5;
  std::vector<int> swapped(16);
  for (int b = 0; b < 16; ++b)
    swapped[b] = 1 - fresh[b];
  EXPECT_FALSE(split_has_drifted(fresh, swapped, 2, heavy, links, 0.1));
  // ... while a split by the weights is more even: worth the move.
  EXPECT_TRUE(split_has_drifted(fresh, partition_bodies(x, heavy, 2), 2, heavy,
                                links, 0.1));
  // A third rank that holds no body counts in the mean: 10 + 6 bodies on
  // two of three ranks is 87.5 % above the mean (25 % over two), and 8 + 8
  // is more even, though neither split names the third part.
  std::vector<int> lopsided(16), halves(16);
  for (int b = 0; b < 16; ++b)
    lopsided[b] = b < 10 ? 0 : 1;
  for (int b = 0; b < 16; ++b)
    halves[b] = b < 8 ? 0 : 1;
  EXPECT_TRUE(split_has_drifted(lopsided, halves, 3, w, {}, 0.3));
  EXPECT_FALSE(split_has_drifted(lopsided, halves, 2, w, {}, 0.3));
}
