// Gauss–Seidel's drift along a singular contact set and its extrapolation
// (drift_extrapolation.h): one node touching a frictionless base and a
// rigid neighbour with friction, whose answer is known by hand.
#include "drift_extrapolation.h"
#include "error.h"
#include "nlgs.h"
#include "rim_node.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace softpack::contact;

namespace
{
using namespace rim_node;
FrictionContactProblem3D rim_node_problem()
{
  return rim_node::problem();
}

NlgsOptions options(NlgsExtrapolation extrapolation)
{
  NlgsOptions o;
  o.tolerance = 1e-10;
  o.relaxation = 1.0;
  o.max_sweeps = 100000;
  o.full_error_interval = 1;
  o.extrapolation = extrapolation;
  return o;
}
} // namespace

TEST(DriftExtrapolation, GaussSeidelCreepsAlongTheRimNodesSegment)
{
  // Each sweep moves the base's reaction and the neighbour's friction by
  // slip / c: the friction reaches mu r_n = mu v0 / c after mu v0 / slip =
  // 3,000 sweeps.
  const FrictionContactProblem3D p = rim_node_problem();
  std::vector<double> r(6, 0.0), u(6);
  const NlgsResult plain = solve_nlgs(p, r, u, options(NlgsExtrapolation::off));
  EXPECT_TRUE(plain.converged);
  EXPECT_GT(plain.iterations, 2500);
  EXPECT_EQ(plain.extrapolations, 0);
}

namespace
{
void check_answer(const FrictionContactProblem3D& p, std::span<double> r,
                  std::span<double> u, const NlgsResult& result)
{
  EXPECT_TRUE(result.converged);
  EXPECT_LE(result.iterations, 20);
  EXPECT_GE(result.extrapolations, 1);
  expect_answer(r, 1e-8);
  EXPECT_LE(compute_error(p, r, u, 1e-12).value, 1e-10);
}
} // namespace

TEST(DriftExtrapolation, FollowsTheDriftToTheConeAndFindsTheAnswer)
{
  // Both paths of solve_nlgs(): rows read in place (`row`) and the
  // renumbered, velocity-updated sweeps
  for (const NlgsUpdate update : {NlgsUpdate::row, NlgsUpdate::velocity})
  {
    SCOPED_TRACE(update == NlgsUpdate::row ? "row" : "velocity");
    const FrictionContactProblem3D p = rim_node_problem();
    std::vector<double> r(6, 0.0), u(6);
    NlgsOptions o = options(NlgsExtrapolation::on);
    o.update = update;
    check_answer(p, r, u, solve_nlgs(p, r, u, o));
  }
}

TEST(DriftExtrapolation, AutomaticIsOnIn3DOnlyAndOnInBoth)
{
  NlgsOptions o;
  o.extrapolation = nlgs_extrapolation("auto");
  EXPECT_TRUE(extrapolates<3>(o));
  EXPECT_FALSE(extrapolates<2>(o));
  o.extrapolation = nlgs_extrapolation("on");
  EXPECT_TRUE(extrapolates<3>(o));
  EXPECT_TRUE(extrapolates<2>(o));
  o.extrapolation = nlgs_extrapolation("off");
  EXPECT_FALSE(extrapolates<3>(o));
  EXPECT_FALSE(extrapolates<2>(o));
  EXPECT_THROW(nlgs_extrapolation("yes"), std::invalid_argument);
}

TEST(DriftExtrapolation, UndoesAJumpThatRaisesTheError)
{
  // A frictionless contact, W = 1, q = -1: the answer is r_n = 1. Sweeps
  // that approach it by the same 1e-3 again and again look like a drift
  // that no cone stops; followed for max_step sweeps, r_n would be 10.5
  // and the relative error 0.90 instead of 0.50 (residual 9.5 over the
  // scale 10.5), so every jump is undone and r is exactly what the sweeps
  // made.
  FrictionContactProblem3D p;
  p.W = DelassusMatrix3D(1);
  p.W.add_block(0, 0, Eigen::Matrix3d::Identity());
  p.W.finalize();
  p.q = {-1.0, 0, 0};
  p.friction = {0.0};
  validate(p);
  std::vector<double> r = {0.5, 0, 0};
  DriftExtrapolation<3> extrapolation(p);
  for (int sweep = 0; sweep < 200; ++sweep)
  {
    const double swept = r[0];
    EXPECT_FALSE(extrapolation.after_sweep(r));
    EXPECT_EQ(r[0], swept);
    r[0] += 1e-3;
  }
  EXPECT_EQ(extrapolation.extrapolations(), 0);
  // a drift is seen every third sweep (two changes, then a fresh start)
  EXPECT_GE(extrapolation.undone(), 60);
}
