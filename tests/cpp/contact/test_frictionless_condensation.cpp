// Frictionless sets held exactly out of the sweeps
// (frictionless_condensation.h): answers by hand, the active set both ways,
// and the whole problem's error.
#include "error.h"
#include "frictionless_condensation.h"
#include "rim_node.h"

#include <gtest/gtest.h>

#include <random>

using namespace softpack::contact;

namespace
{
using namespace rim_node;
/// The rim node with a free node beside it (rim_node.h)
FrictionContactProblem3D rim_node_problem(double base_speed = -v0)
{
  return rim_node::problem(base_speed, true);
}

/// Three nodes of one body (a random SPD compliance G, 9 x 9), one
/// contact each: node 0 on a frictionless base (normal z), nodes 1 and 2
/// against neighbours with friction (normals x and y), all three closing.
/// W = H G H^T is definite, so the answer is unique; the base contact,
/// held, has two neighbours: its correction is a rank-one term.
FrictionContactProblem3D one_body_problem()
{
  std::mt19937 random(7);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Eigen::Matrix<double, 9, 9> A;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      A(i, j) = entry(random);
  const Eigen::Matrix<double, 9, 9> G =
      c * (A * A.transpose() / 9 + Eigen::Matrix<double, 9, 9>::Identity());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(),
                        y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d R[3]; // columns n, t1, t2
  R[0] << z, x, y;
  R[1] << x, y, z;
  R[2] << y, z, x;
  const Eigen::Vector3d v[3] = {
      {0.01, 0.0, -v0}, {-v0, 0.02, 0.0}, {0.0, -v0, 0.03}};
  FrictionContactProblem3D p;
  p.W = DelassusMatrix3D(3);
  for (int a = 0; a < 3; ++a)
  {
    for (int b = 0; b < 3; ++b)
      p.W.add_block(a, b,
                    R[a].transpose() * G.block<3, 3>(3 * a, 3 * b) * R[b]);
    const Eigen::Vector3d qa = R[a].transpose() * v[a];
    p.q.insert(p.q.end(), {qa[0], qa[1], qa[2]});
  }
  p.W.finalize();
  p.friction = {0.0, mu, mu};
  validate(p);
  return p;
}

NlgsOptions options()
{
  NlgsOptions o;
  o.tolerance = 1e-10;
  o.relaxation = 1.0;
  o.max_sweeps = 100000;
  o.full_error_interval = 1;
  return o;
}
} // namespace

TEST(FrictionlessCondensation, HoldsTheRimNodeOnTheBaseAndFindsTheAnswer)
{
  // Plain Gauss–Seidel creeps for ~3,000 sweeps here
  // (DriftExtrapolation.GaussSeidelCreepsAlongTheRimNodesSegment). With
  // the base held the node cannot move vertically, the neighbour's
  // vertical slip is what it is whatever its friction, and it slides at
  // once.
  const FrictionContactProblem3D p = rim_node_problem();
  std::vector<double> r(9, 0.0), u(9);
  FrictionlessCondensation<3> condensation(p);
  EXPECT_EQ(condensation.condensed(), 1u);
  const CondensedResult result = condensation.solve(p, r, u, options());
  EXPECT_TRUE(result.nlgs.converged);
  EXPECT_LE(result.nlgs.iterations, 5);
  EXPECT_EQ(result.held, 1u);
  EXPECT_EQ(result.rounds, 1);
  // one held contact, one neighbour: its correction is a block
  EXPECT_EQ(result.held_terms, 0u);
  expect_answer(r, 1e-12);
  EXPECT_NEAR(r[6], v0 / c, 1e-12 * v0 / c);
  // The error is the whole problem's, recomputed here
  std::vector<double> u_check(9);
  EXPECT_LE(compute_error(p, r, u_check, 1e-12).value, 1e-10);
  EXPECT_NEAR(u[2], u_check[2], 1e-15);
}

TEST(FrictionlessCondensation, AHeldContactWithMoreNeighboursIsARankOneTerm)
{
  // The held base contact's correction kept as a rank-one term gives the
  // answer of the whole problem swept (unique: W is definite)
  const FrictionContactProblem3D p = one_body_problem();
  std::vector<double> r(9, 0.0), u(9), r_plain(9, 0.0), u_plain(9);
  const CondensedResult result =
      FrictionlessCondensation<3>(p).solve(p, r, u, options());
  const NlgsResult plain = solve_nlgs(p, r_plain, u_plain, options());
  ASSERT_TRUE(result.nlgs.converged);
  ASSERT_TRUE(plain.converged);
  EXPECT_EQ(result.held, 1u);
  EXPECT_EQ(result.held_terms, 1u);
  EXPECT_GT(r[0], 0.0);
  const double scale = v0 / c;
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(r[i], r_plain[i], 1e-8 * scale) << "component " << i;
  std::vector<double> u_check(9);
  EXPECT_LE(compute_error(p, r, u_check, 1e-12).value, 1e-10);
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(u[i], u_check[i], 1e-12 * v0) << "component " << i;
}

TEST(FrictionlessCondensation, SweepsTheWholeProblemWithTheBudgetsSecondHalf)
{
  // Given 4 sweeps, the held rounds stop after 2 without an answer and
  // the whole problem is swept from theirs with the other 2; its error is
  // the whole problem's at the end. With enough sweeps the held rounds
  // find the answer alone.
  const FrictionContactProblem3D p = one_body_problem();
  NlgsOptions few = options();
  few.max_sweeps = 4;
  std::vector<double> r(9, 0.0), u(9), u_check(9);
  const CondensedResult cut =
      FrictionlessCondensation<3>(p).solve(p, r, u, few);
  EXPECT_EQ(cut.swept_whole, 2);
  EXPECT_EQ(cut.nlgs.iterations, 4);
  EXPECT_FALSE(cut.nlgs.converged);
  EXPECT_DOUBLE_EQ(cut.nlgs.error, compute_error(p, r, u_check, 1e-12).value);
  std::fill(r.begin(), r.end(), 0.0);
  const CondensedResult enough =
      FrictionlessCondensation<3>(p).solve(p, r, u, options());
  EXPECT_TRUE(enough.nlgs.converged);
  EXPECT_EQ(enough.swept_whole, 0);
}

TEST(FrictionlessCondensation, LetsGoOfABaseContactThatWouldPull)
{
  // The node rises off the base fast enough that the neighbour's friction
  // (at most mu v0 down) cannot hold it: started held (a pushing reaction
  // from the last step), its reaction comes out pulling, it is let go and
  // the node leaves the base: r = 0 there, u_n > 0.
  const FrictionContactProblem3D p = rim_node_problem(+2 * mu * v0);
  std::vector<double> r(9, 0.0), u(9);
  r[0] = v0 / c;
  const CondensedResult result =
      FrictionlessCondensation<3>(p).solve(p, r, u, options());
  EXPECT_TRUE(result.nlgs.converged);
  EXPECT_EQ(result.rounds, 2);
  EXPECT_EQ(result.held, 0u);
  EXPECT_EQ(r[0], 0.0);
  EXPECT_GT(u[0], 0.0);
  std::vector<double> u_check(9);
  EXPECT_LE(compute_error(p, r, u_check, 1e-12).value, 1e-10);
}

TEST(FrictionlessCondensation, SweepsABaseContactThatWasNotPushing)
{
  // The node rises slowly (less than the neighbour's friction pulls it
  // down): at the start the base contact has no reaction and an opening
  // free velocity, so it is not held but swept with the others, and the
  // sweeps close it. The next solve on this W (a Newton iteration of the
  // same step) keeps it swept; a new W's first solve (the next time step,
  // warm started from this answer) holds it.
  const double rise = 0.5 * mu * v0;
  const FrictionContactProblem3D p = rim_node_problem(rise);
  std::vector<double> r(9, 0.0), u(9);
  FrictionlessCondensation<3> condensation(p);
  const CondensedResult first = condensation.solve(p, r, u, options());
  EXPECT_TRUE(first.nlgs.converged);
  EXPECT_EQ(first.held, 0u);
  // Swept, the pair creeps as plain Gauss–Seidel does, in rounds of 500
  // sweeps (nothing to let go between them)
  EXPECT_GT(first.nlgs.iterations, 500);
  EXPECT_EQ(first.rounds, (first.nlgs.iterations + 499) / 500);
  const double scale = v0 / c;
  EXPECT_NEAR(r[0], mu * scale - rise / c, 1e-8 * scale);
  EXPECT_NEAR(r[5], -mu * scale, 1e-8 * scale);
  const CondensedResult same = condensation.solve(p, r, u, options());
  EXPECT_TRUE(same.nlgs.converged);
  EXPECT_EQ(same.held, 0u);
  const CondensedResult next =
      FrictionlessCondensation<3>(p).solve(p, r, u, options());
  EXPECT_TRUE(next.nlgs.converged);
  EXPECT_EQ(next.held, 1u);
  EXPECT_LE(next.nlgs.iterations, 2);
  EXPECT_NEAR(r[0], mu * scale - rise / c, 1e-8 * scale);
  std::vector<double> u_check(9);
  EXPECT_LE(compute_error(p, r, u_check, 1e-12).value, 1e-10);
}

TEST(FrictionlessCondensation, WithoutFrictionlessSetsIsThePlainSolve)
{
  FrictionContactProblem3D p = rim_node_problem();
  p.friction[0] = mu; // nothing to condense
  std::vector<double> r(9, 0.0), u(9), r_plain(9, 0.0), u_plain(9);
  const CondensedResult result =
      FrictionlessCondensation<3>(p).solve(p, r, u, options());
  const NlgsResult plain = solve_nlgs(p, r_plain, u_plain, options());
  EXPECT_EQ(result.condensed, 0u);
  EXPECT_EQ(result.nlgs.iterations, plain.iterations);
  EXPECT_EQ(r, r_plain);
}

TEST(FrictionlessCondensation, RefusesAnotherWAndOtherNames)
{
  const FrictionContactProblem3D p = rim_node_problem(),
                                 other = rim_node_problem();
  std::vector<double> r(9, 0.0), u(9);
  FrictionlessCondensation<3> condensation(p);
  EXPECT_THROW(condensation.solve(other, r, u, options()),
               std::invalid_argument);
  EXPECT_TRUE(condenses("on", 3));
  EXPECT_FALSE(condenses("off", 3));
  EXPECT_FALSE(condenses("off", 2));
  EXPECT_THROW(condenses("on", 2), std::invalid_argument);
  EXPECT_TRUE(condenses("auto", 3));
  EXPECT_FALSE(condenses("auto", 2));
  EXPECT_THROW(condenses("yes", 3), std::invalid_argument);
}
