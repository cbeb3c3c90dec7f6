// NLGS on hand-made 1- and 2-contact problems with known answers (open,
// stick, slide both ways, mu = 0), and its options.

#include "error.h"
#include "helpers.h"
#include "nlgs.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
/// Two contacts sharing a body: symmetric positive definite, coupled.
Eigen::MatrixXd coupled_W()
{
  Eigen::MatrixXd W(4, 4);
  W << 2.0, 0.2, 0.3, 0.1,   //
      0.2, 1.0, -0.05, 0.2,  //
      0.3, -0.05, 1.5, -0.1, //
      0.1, 0.2, -0.1, 0.8;
  return W;
}

/// A problem whose solution is (r, u): q = u - W r.
FrictionContactProblem2D manufactured(const Eigen::MatrixXd& W,
                                      const Eigen::VectorXd& r,
                                      const Eigen::VectorXd& u,
                                      const std::vector<double>& mu)
{
  return make_problem(W, u - W * r, mu);
}

void expect_solves_to(const FrictionContactProblem2D& p,
                      const Eigen::VectorXd& r_expected, int max_sweeps)
{
  std::vector<double> r(r_expected.size(), 0.0), u(r.size());
  const NlgsResult res = solve_nlgs(p, r, u);
  EXPECT_TRUE(res.converged);
  EXPECT_LE(res.error, 1e-8);
  EXPECT_LE(res.iterations, max_sweeps);
  // exact on the one-contact problems, at most 4.6e-10 off on the coupled
  // ones (measured 2026-12-03)
  for (int k = 0; k < r_expected.size(); ++k)
    EXPECT_NEAR(r[k], r_expected[k], 5e-9) << "entry " << k;
}
} // namespace

TEST(Nlgs, OneContactEveryBranch)
{
  const Eigen::MatrixXd W = Eigen::Vector2d(2, 1).asDiagonal();
  // open, stick, slide with u_t > 0, slide with u_t < 0, mu = 0
  expect_solves_to(make_problem(W, Eigen::Vector2d(1, 3), {0.3}),
                   Eigen::Vector2d(0, 0), 2);
  expect_solves_to(make_problem(W, Eigen::Vector2d(-2, 0.1), {0.3}),
                   Eigen::Vector2d(1, -0.1), 2);
  expect_solves_to(make_problem(W, Eigen::Vector2d(-2, 1), {0.3}),
                   Eigen::Vector2d(1, -0.3), 2);
  expect_solves_to(make_problem(W, Eigen::Vector2d(-2, -1), {0.3}),
                   Eigen::Vector2d(1, 0.3), 2);
  expect_solves_to(make_problem(W, Eigen::Vector2d(-2, -1), {0.0}),
                   Eigen::Vector2d(1, 0), 2);
}

TEST(Nlgs, TwoCoupledContactsStickAndSlide)
{
  const double mu = 0.4;
  Eigen::VectorXd r(4), u(4);
  r << 1, 0.1, 2, -mu * 2; // stick; slide with u_t > 0
  u << 0, 0, 0, 0.5;
  expect_solves_to(manufactured(coupled_W(), r, u, {mu, mu}), r, 100);
}

TEST(Nlgs, TwoCoupledContactsOpenAndSlideBack)
{
  const double mu = 0.4;
  Eigen::VectorXd r(4), u(4);
  r << 0, 0, 1, mu; // open; slide with u_t < 0
  u << 0.3, -1, 0, -0.2;
  expect_solves_to(manufactured(coupled_W(), r, u, {mu, mu}), r, 100);
}

TEST(Nlgs, TwoCoupledContactsFrictionless)
{
  Eigen::VectorXd r(4), u(4);
  r << 1, 0, 0.5, 0;
  u << 0, 0.3, 0, -0.1;
  expect_solves_to(manufactured(coupled_W(), r, u, {0.0, 0.0}), r, 100);
}

TEST(Nlgs, TwoCoupledContactsBothStick)
{
  Eigen::VectorXd r(4), u(4);
  r << 1, 0.2, 0.5, -0.1;
  u << 0, 0, 0, 0;
  expect_solves_to(manufactured(coupled_W(), r, u, {0.5, 0.5}), r, 100);
}

TEST(Nlgs, RelaxationReachesTheSameAnswer)
{
  Eigen::VectorXd r_star(4), u_star(4);
  r_star << 1, 0.1, 2, -0.8;
  u_star << 0, 0, 0, 0.5;
  const FrictionContactProblem2D p =
      manufactured(coupled_W(), r_star, u_star, {0.4, 0.4});
  for (double omega : {0.6, 1.3})
  {
    NlgsOptions opt;
    opt.relaxation = omega;
    std::vector<double> r(4, 0.0), u(4);
    const NlgsResult res = solve_nlgs(p, r, u, opt);
    EXPECT_TRUE(res.converged) << omega;
    // measured 1.8e-8 (omega 0.6) and 1.2e-8 (1.3) off, 2026-12-03
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(r[k], r_star[k], 1e-7) << omega;
  }
  NlgsOptions bad;
  bad.relaxation = 2.0;
  std::vector<double> r(4, 0.0), u(4);
  EXPECT_THROW(solve_nlgs(p, r, u, bad), std::invalid_argument);
}

TEST(Nlgs, WarmStartFromTheAnswerTakesOneSweep)
{
  Eigen::VectorXd r_star(4), u_star(4);
  r_star << 1, 0.1, 2, -0.8;
  u_star << 0, 0, 0, 0.5;
  const FrictionContactProblem2D p =
      manufactured(coupled_W(), r_star, u_star, {0.4, 0.4});
  std::vector<double> r(r_star.data(), r_star.data() + 4), u(4);
  NlgsResult res = solve_nlgs(p, r, u);
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 1);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(u[k], u_star[k], 1e-14);

  // warm_start = false ignores the reactions passed in
  NlgsOptions cold;
  cold.warm_start = false;
  cold.max_sweeps = 1;
  r.assign(r_star.data(), r_star.data() + 4);
  res = solve_nlgs(p, r, u, cold);
  EXPECT_FALSE(res.converged);
}

TEST(Nlgs, MaxSweepsAndTolerance)
{
  Eigen::VectorXd r_star(4), u_star(4);
  r_star << 1, 0.1, 2, -0.8;
  u_star << 0, 0, 0, 0.5;
  const FrictionContactProblem2D p =
      manufactured(coupled_W(), r_star, u_star, {0.4, 0.4});
  std::vector<double> r(4, 0.0), u(4);
  NlgsOptions opt;
  opt.max_sweeps = 0;
  NlgsResult res = solve_nlgs(p, r, u, opt);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_FALSE(res.converged);

  opt.max_sweeps = 1000;
  for (double tol : {1e-4, 1e-12})
  {
    opt.tolerance = tol;
    std::fill(r.begin(), r.end(), 0.0);
    res = solve_nlgs(p, r, u, opt);
    EXPECT_TRUE(res.converged);
    EXPECT_LE(res.error, tol);
    std::vector<double> u2(4);
    EXPECT_EQ(compute_error(p, r, u2, opt.q_zero_tolerance).value, res.error);
  }
}

TEST(Nlgs, QZeroGivesZeroReactionsWithoutASweep)
{
  const FrictionContactProblem2D p = make_problem(
      coupled_W(), Eigen::Vector4d(1e-16, -1e-16, -2e-16, 0), {0.4, 0.4});
  std::vector<double> r = {1, 1, 1, 1}, u(4);
  const NlgsResult res = solve_nlgs(p, r, u);
  EXPECT_TRUE(res.q_zero);
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_EQ(r, std::vector<double>(4, 0.0));
  EXPECT_LT(res.error, 1e-15);
}

TEST(Nlgs, RejectsWrongSizes)
{
  const FrictionContactProblem2D p =
      make_problem(coupled_W(), Eigen::Vector4d(-1, 0, -1, 0), {0.4, 0.4});
  std::vector<double> r(3), u(4);
  EXPECT_THROW(solve_nlgs(p, r, u), std::invalid_argument);
}
