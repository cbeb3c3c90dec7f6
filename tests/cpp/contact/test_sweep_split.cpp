// The split behind the two-thread NLGS sweep: its parts never couple, it
// cuts where a hand count says, and a split solve gives the same bits on
// one thread and on two, solving every FCLIB problem to its error.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"
#include "sweep_split.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
/// Contacts coupled like the links of a chain (a with a + 1), in `groups`
/// separate chains of `length` contacts each.
DelassusMatrix chains(int groups, int length)
{
  DelassusMatrix W(groups * length);
  for (int g = 0; g < groups; ++g)
    for (int i = 0; i < length; ++i)
    {
      const int a = g * length + i;
      W.add_block(a, a, 2 * Eigen::Matrix2d::Identity());
      if (i + 1 < length)
      {
        W.add_block(a, a + 1, 0.1 * Eigen::Matrix2d::Identity());
        W.add_block(a + 1, a, 0.1 * Eigen::Matrix2d::Identity());
      }
    }
  W.finalize();
  return W;
}

/// Every contact once, and no block between the two parts.
void expect_valid(const DelassusMatrix& W, const SweepSplit& split)
{
  std::vector<int> where(W.num_contacts(), -1);
  for (int set = 0; set < 3; ++set)
    for (const std::int32_t a : set < 2 ? split.part[set] : split.separator)
    {
      ASSERT_EQ(where[a], -1) << "contact " << a << " twice";
      where[a] = set;
    }
  for (std::size_t a = 0; a < W.num_contacts(); ++a)
  {
    ASSERT_NE(where[a], -1) << "contact " << a << " missing";
    for (const std::int32_t b : W.row_columns(a))
      EXPECT_FALSE(where[a] < 2 && where[b] < 2 && where[a] != where[b])
          << "block (" << a << ", " << b << ") couples the two parts";
  }
}
} // namespace

TEST(SweepSplit, OneChainIsCutInItsMiddle)
{
  // Nine links, equal work: levels 0..8 from an end; the cut that balances
  // max(before, after) + level is level 4.
  const DelassusMatrix W = chains(1, 9);
  const SweepSplit split = split_for_two_threads(W);
  expect_valid(W, split);
  EXPECT_EQ(split.separator, std::vector<std::int32_t>{4});
  EXPECT_EQ(split.part[0].size() + split.part[1].size(), 8u);
  EXPECT_EQ(split.part[0].size(), 4u);
}

TEST(SweepSplit, SeparateComponentsNeedNoSeparatorBetweenThem)
{
  // Two chains of three (work 2, 3, 2 each): levels 0-2 and 3-5 laid end
  // to end; the best cut costs max(5, 7) + 2 = 9 at level 2 (or 3): one
  // contact as separator, and the parts never couple.
  const DelassusMatrix W = chains(2, 3);
  const SweepSplit split = split_for_two_threads(W);
  expect_valid(W, split);
  EXPECT_EQ(split.separator.size(), 1u);
}

TEST(SweepSplit, ALocalTermKeepsToOneSideOfTheSeparator)
{
  // The chain of nine with a rank-one term over contacts 1, 2 and 7, which
  // the plain chain's split puts in different parts. Local: the split is
  // the plain chain's but for the term's contacts in part 1, which join
  // the separator. Spread: all three are the separator.
  const SweepSplit plain = split_for_two_threads(chains(1, 9));
  std::vector<int> plain_side(9, 2);
  for (int k = 0; k < 2; ++k)
    for (const std::int32_t a : plain.part[k])
      plain_side[a] = k;
  const std::vector<std::int32_t> term{1, 2, 7};
  ASSERT_NE(plain_side[1], plain_side[7]);
  ASSERT_NE(plain_side[7], 2);
  using Reach = DelassusMatrix::Reach;
  for (const Reach reach : {Reach::local, Reach::spread})
  {
    DelassusMatrix W(9);
    for (int a = 0; a < 9; ++a)
    {
      W.add_block(a, a, 2 * Eigen::Matrix2d::Identity());
      if (a + 1 < 9)
      {
        W.add_block(a, a + 1, 0.1 * Eigen::Matrix2d::Identity());
        W.add_block(a + 1, a, 0.1 * Eigen::Matrix2d::Identity());
      }
    }
    const std::vector<Eigen::Vector2d> g(3, Eigen::Vector2d(1.0, 0.0));
    W.add_rank_one(term, g, 1.0, true, reach);
    W.finalize();
    const SweepSplit split = split_for_two_threads(W);
    expect_valid(W, split);
    std::vector<int> side(9, 2);
    for (int k = 0; k < 2; ++k)
      for (const std::int32_t a : split.part[k])
        side[a] = k;
    for (int a = 0; a < 9; ++a)
    {
      const bool in_term = std::count(term.begin(), term.end(), a) > 0;
      if (reach == Reach::spread and in_term)
        EXPECT_EQ(side[a], 2) << "contact " << a;
      else if (reach == Reach::local)
        EXPECT_EQ(side[a], in_term and plain_side[a] == 1 ? 2 : plain_side[a])
            << "contact " << a;
    }
  }
}

TEST(SweepSplit, FclibProblemsSplitIntoUncoupledParts)
{
  for (const DataProblem& d : data_problems())
  {
    const FrictionContactProblem2D p = read_fclib_local(hdf5_file(d.name));
    const SweepSplit split = split_for_two_threads(p.W);
    std::cout << "[ split    ] " << d.name << ": " << split.part[0].size()
              << " | " << split.part[1].size() << " | separator "
              << split.separator.size() << "\n";
    expect_valid(p.W, split);
  }
}

TEST(SweepSplit, SameBitsOnOneThreadAndOnTwo)
{
  const FrictionContactProblem2D p =
      read_fclib_local(hdf5_file("fc2d_granularflowonwall_02020_00213"));
  for (const SweepOrder order : {SweepOrder::contact, SweepOrder::alternate})
  {
    NlgsOptions opt;
    opt.tolerance = 1e-6;
    opt.split_min_contacts = 1;
    opt.order = order;
    std::vector<double> r1(2 * p.num_contacts(), 0.0), u1(r1.size());
    std::vector<double> r2 = r1, u2 = u1;
    opt.threads = 1;
    const NlgsResult one = solve_nlgs(p, r1, u1, opt);
    opt.threads = 2;
    const NlgsResult two = solve_nlgs(p, r2, u2, opt);
    EXPECT_TRUE(one.converged);
    EXPECT_EQ(one.iterations, two.iterations);
    EXPECT_EQ(r1, r2);
    EXPECT_EQ(one.error, two.error);
  }
}

TEST(SweepSplit, SplitSolvesEveryFclibProblemToItsError)
{
  for (const DataProblem& d : data_problems())
  {
    const FrictionContactProblem2D p = read_fclib_local(hdf5_file(d.name));
    NlgsOptions opt;
    opt.tolerance = d.tolerance;
    opt.max_sweeps = 10000;
    opt.split_min_contacts = 1;
    opt.threads = 2;
    std::vector<double> r(2 * p.num_contacts(), 0.0), u(r.size());
    const NlgsResult res = solve_nlgs(p, r, u, opt);
    EXPECT_TRUE(res.converged) << d.name;
    // The error again, from the returned reactions alone.
    std::vector<double> w(r.size());
    EXPECT_LE(compute_error(p, r, w, opt.q_zero_tolerance).value, d.tolerance)
        << d.name;
  }
}
