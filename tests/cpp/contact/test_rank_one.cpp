// W's rank-one terms (DelassusMatrix::RankOne, a servo unknown's
// compliance): the NLGS that keeps one running sum per term against the
// same W assembled as dense blocks, on a small random problem of point
// bodies whose W is also formed independently as H M^-1 H^T.
#include "DelassusMatrix.h"
#include "error.h"
#include "fclib_io.h"
#include "nlgs.h"
#include "sweep_split.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <gtest/gtest.h>
#include <random>
#include <unistd.h>

using namespace softpack::contact;

namespace
{
/// A random 2D problem: point bodies (2 DOFs, mass m_i), each contact
/// between two of them in a random frame; two servo unknowns, one moved by
/// every contact (`cell`; else a fifth of them), one by a third of them
/// (as a cell's component and a wall). W is stored as the bodies' blocks plus
/// the two rank-one terms; `dense` is the whole W formed as a matrix.
struct RandomProblem
{
  FrictionContactProblem2D problem;
  Eigen::MatrixXd dense;
};

RandomProblem random_problem(std::size_t n, int bodies, unsigned seed,
                             bool cell = true)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> body(0, bodies - 1);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * n, 2 * bodies + 2);
  std::vector<std::pair<int, int>> pair(n);
  for (std::size_t a = 0; a < n; ++a)
  {
    const int i = body(gen);
    int j = body(gen);
    while (j == i)
      j = body(gen);
    pair[a] = {i, j};
    const double angle = 2 * M_PI * unit(gen);
    Eigen::Matrix2d frame;
    frame << std::cos(angle), -std::sin(angle), std::sin(angle),
        std::cos(angle);
    H.block(2 * a, 2 * i, 2, 2) = frame.transpose();
    H.block(2 * a, 2 * j, 2, 2) = -frame.transpose();
  }
  std::vector<double> inverse_mass(bodies + 2);
  for (double& w : inverse_mass)
    w = 0.5 + unit(gen);
  // The two servo unknowns' g (their DOFs are the last two columns)
  std::vector<std::vector<std::int32_t>> contacts(2);
  std::vector<std::vector<Eigen::Vector2d>> g(2);
  for (std::size_t a = 0; a < n; ++a)
    for (int k = 0; k < 2; ++k)
      if ((k == 0 and (cell or a % 5 == 0)) or (k == 1 and a % 3 == 1))
      {
        const Eigen::Vector2d gk(unit(gen) - 0.5, unit(gen) - 0.5);
        contacts[k].push_back(static_cast<std::int32_t>(a));
        g[k].push_back(gk);
        H(2 * a, 2 * bodies + k) = gk[0];
        H(2 * a + 1, 2 * bodies + k) = gk[1];
      }
  Eigen::VectorXd Minv(2 * bodies + 2);
  for (int i = 0; i < bodies; ++i)
    Minv.segment<2>(2 * i).setConstant(inverse_mass[i]);
  Minv.tail<2>() << inverse_mass[bodies], inverse_mass[bodies + 1];
  // Each contact's own compliance (a deformable body's local one), which
  // makes W definite with more contacts than DOFs
  const double local = 2.0;
  RandomProblem out;
  out.dense = H * Minv.asDiagonal() * H.transpose() +
              local * Eigen::MatrixXd::Identity(2 * n, 2 * n);
  // The bodies' blocks: contacts sharing a body
  FrictionContactProblem2D& p = out.problem;
  p.W = DelassusMatrix(n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b)
    {
      Eigen::Matrix2d block = Eigen::Matrix2d::Zero();
      for (int i = 0; i < bodies; ++i)
        block += inverse_mass[i] * H.block(2 * a, 2 * i, 2, 2) *
                 H.block(2 * b, 2 * i, 2, 2).transpose();
      const auto [ai, aj] = pair[a];
      const auto [bi, bj] = pair[b];
      if (a == b)
        block += local * Eigen::Matrix2d::Identity();
      if (a == b or ai == bi or ai == bj or aj == bi or aj == bj)
        p.W.add_block(a, b, block);
    }
  for (int k = 0; k < 2; ++k)
    p.W.add_rank_one(contacts[k], g[k], inverse_mass[bodies + k]);
  p.W.finalize();
  p.q.resize(2 * n);
  for (double& v : p.q)
    v = 2 * unit(gen) - 1.3;
  p.friction.assign(n, 0.3);
  validate(p);
  return out;
}

/// The problem with its rank-one terms stored as blocks (as W was
/// assembled before the terms)
FrictionContactProblem2D as_blocks(const FrictionContactProblem2D& p)
{
  FrictionContactProblem2D blocks = p;
  blocks.W = p.W.expanded();
  return blocks;
}

double largest(const std::vector<double>& x)
{
  double m = 0;
  for (const double v : x)
    m = std::max(m, std::abs(v));
  return m;
}

struct Outcome
{
  std::vector<double> r, u;
  NlgsResult result;
};

Outcome solve(const FrictionContactProblem2D& p, const NlgsOptions& options)
{
  Outcome run{std::vector<double>(2 * p.num_contacts(), 0.0),
              std::vector<double>(2 * p.num_contacts()),
              {}};
  run.result = solve_nlgs(p, run.r, run.u, options);
  return run;
}
} // namespace

TEST(RankOne, TheOperatorIsTheWholeW)
{
  const RandomProblem rp = random_problem(30, 8, 1);
  const DelassusMatrix& W = rp.problem.W;
  EXPECT_EQ(W.rank_one_terms().size(), 2u);
  // No block of the terms is stored
  const DelassusMatrix blocks = W.expanded();
  EXPECT_LT(W.num_offdiagonal_blocks(), blocks.num_offdiagonal_blocks());
  std::mt19937 gen(7);
  std::normal_distribution<double> normal;
  std::vector<double> r(60), u(60, 0.0), u_blocks(60, 0.0);
  for (double& v : r)
    v = normal(gen);
  W.multiply_add(r, u);
  blocks.multiply_add(r, u_blocks);
  const Eigen::VectorXd reference =
      rp.dense * Eigen::Map<const Eigen::VectorXd>(r.data(), 60);
  for (std::size_t i = 0; i < 60; ++i)
  {
    EXPECT_NEAR(u[i], reference[i],
                1e-13 * reference.lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(u_blocks[i], reference[i],
                1e-13 * reference.lpNorm<Eigen::Infinity>());
  }
  // Renumbered, the terms follow their contacts
  std::vector<std::int32_t> order(30);
  for (std::size_t i = 0; i < 30; ++i)
    order[i] = static_cast<std::int32_t>((7 * i) % 30);
  const DelassusMatrix moved = W.renumbered(order);
  std::vector<double> r_moved(60), u_moved(60, 0.0);
  for (std::size_t i = 0; i < 30; ++i)
    for (int c = 0; c < 2; ++c)
      r_moved[2 * i + c] = r[2 * order[i] + c];
  moved.multiply_add(r_moved, u_moved);
  for (std::size_t i = 0; i < 30; ++i)
    for (int c = 0; c < 2; ++c)
      EXPECT_NEAR(u_moved[2 * i + c], u[2 * order[i] + c],
                  1e-13 * reference.lpNorm<Eigen::Infinity>());
}

TEST(RankOne, TheNlgsGivesTheDenseAnswerToRoundOff)
{
  // (velocity-updated sweeps too: the terms read from their sums, the
  // blocks from the kept velocities; against the blocks' row sweeps)
  for (NlgsUpdate update : {NlgsUpdate::row, NlgsUpdate::velocity})
    for (unsigned seed : {1u, 2u, 3u})
      for (double relaxation : {1.0, 1.7})
      {
        const RandomProblem rp = random_problem(40, 10, seed);
        NlgsOptions options;
        options.tolerance = 1e-10;
        options.relaxation = relaxation;
        options.order =
            relaxation == 1.0 ? SweepOrder::contact : SweepOrder::alternate;
        options.update = NlgsUpdate::row;
        const FrictionContactProblem2D blocks = as_blocks(rp.problem);
        const Outcome b = solve(blocks, options);
        options.update = update;
        const Outcome a = solve(rp.problem, options);
        ASSERT_TRUE(a.result.converged);
        ASSERT_TRUE(b.result.converged);
        // The same Gauss–Seidel iteration: the same sweeps, the reactions
        // apart by rounding
        EXPECT_EQ(a.result.iterations, b.result.iterations);
        const double scale = largest(b.r);
        ASSERT_GT(scale, 0);
        for (std::size_t i = 0; i < a.r.size(); ++i)
          EXPECT_NEAR(a.r[i], b.r[i], 1e-12 * scale) << "seed " << seed;
        // The error sees the whole W: the rank-one form's and the blocks'
        // agree at the same reactions
        std::vector<double> u(a.u.size());
        const NaturalMapError ea = compute_error(rp.problem, a.r, u, 1e-12);
        const NaturalMapError eb = compute_error(blocks, a.r, u, 1e-12);
        EXPECT_NEAR(ea.value, eb.value, 1e-12);
        EXPECT_LE(eb.value, options.tolerance);
      }
}

TEST(RankOne, ASplitSweepKeepsTheTermsInItsSeparator)
{
  const RandomProblem rp = random_problem(90, 30, 4, false);
  const SweepSplit split = split_for_two_threads(rp.problem.W);
  EXPECT_FALSE(split.part[0].empty());
  EXPECT_FALSE(split.part[1].empty());
  for (const auto& term : rp.problem.W.rank_one_terms())
    for (const std::int32_t c : term.contacts)
      EXPECT_TRUE(std::binary_search(split.separator.begin(),
                                     split.separator.end(), c));
  // Split and swept on one thread or two: the same bits, and the answer of
  // the dense W; row- or velocity-updated
  for (NlgsUpdate update : {NlgsUpdate::row, NlgsUpdate::velocity})
  {
    NlgsOptions options;
    options.tolerance = 1e-10;
    options.relaxation = 1.7;
    options.order = SweepOrder::alternate;
    options.split_min_contacts = 10;
    options.update = update;
    options.threads = 1;
    const Outcome one = solve(rp.problem, options);
    options.threads = 2;
    const Outcome two = solve(rp.problem, options);
    ASSERT_TRUE(one.result.converged);
    EXPECT_EQ(one.r, two.r);
    EXPECT_EQ(one.result.iterations, two.result.iterations);
    std::vector<double> u(one.u.size());
    EXPECT_LE(compute_error(as_blocks(rp.problem), one.r, u, 1e-12).value,
              options.tolerance);
  }
}

TEST(RankOne, AWrittenProblemHasTheTermsAsBlocks)
{
  // A file (an unsolved problem kept for replay) has no rank-one term:
  // written, the terms are blocks, and the problem read back is the same W
  const RandomProblem rp = random_problem(20, 6, 5);
  const auto path = std::filesystem::temp_directory_path() /
                    ("softpack_rank_one_" + std::to_string(::getpid()) + ".h5");
  dump_problem(rp.problem, path);
  const FrictionContactProblem2D back = read_fclib_local(path);
  std::filesystem::remove(path);
  EXPECT_TRUE(back.W.rank_one_terms().empty());
  std::vector<double> r(40), u(40, 0.0), u_back(40, 0.0);
  for (std::size_t i = 0; i < r.size(); ++i)
    r[i] = std::sin(1.0 + static_cast<double>(i));
  rp.problem.W.multiply_add(r, u);
  back.W.multiply_add(r, u_back);
  for (std::size_t i = 0; i < r.size(); ++i)
    EXPECT_NEAR(u_back[i], u[i], 1e-13 * largest(u));
}
