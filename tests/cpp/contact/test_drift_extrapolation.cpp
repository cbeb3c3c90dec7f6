// Gauss–Seidel's drift along a singular contact set and its extrapolation
// (drift_extrapolation.h): one node touching a frictionless base and a
// rigid neighbour with friction, whose answer is known by hand.
#include "drift_extrapolation.h"
#include "error.h"
#include "nlgs.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace softpack::contact;

namespace
{
constexpr double c = 1e5;     // the node's compliance, isotropic (m/s per N s)
constexpr double mu = 0.3;    // the neighbour's friction
constexpr double v0 = 0.1;    // the node's free speed into both (m/s)
constexpr double slip = 1e-5; // the neighbour's vertical speed (m/s)

/// Contact 0: the base, normal z; contact 1: the neighbour, normal x, its
/// second tangent z. Both act on one node of compliance c I, so W is
/// [R_a^T; R_b^T] c [R_a R_b], of rank 3: the base's normal reaction and
/// the neighbour's vertical friction move the node alike. The neighbour
/// moves down by `slip` relative to the base, so the two cannot both hold:
/// the neighbour slides, |r_t| = mu r_n.
FrictionContactProblem3D rim_node()
{
  Eigen::Matrix3d Ra, Rb; // columns n, t1, t2 in world components
  Ra << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  Rb << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  const Eigen::Matrix3d C = c * Eigen::Matrix3d::Identity();
  FrictionContactProblem3D p;
  p.W = DelassusMatrix3D(2);
  p.W.add_block(0, 0, Ra.transpose() * C * Ra);
  p.W.add_block(1, 1, Rb.transpose() * C * Rb);
  p.W.add_block(0, 1, Ra.transpose() * C * Rb);
  p.W.add_block(1, 0, Rb.transpose() * C * Ra);
  p.W.finalize();
  const Eigen::Vector3d v(-v0, 0, -v0);
  const Eigen::Vector3d qa = Ra.transpose() * v;
  Eigen::Vector3d qb = Rb.transpose() * v;
  qb[2] += slip;
  p.q = {qa[0], qa[1], qa[2], qb[0], qb[1], qb[2]};
  p.friction = {0.0, mu};
  validate(p);
  return p;
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
  const FrictionContactProblem3D p = rim_node();
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
  // By hand: the neighbour holds the node's horizontal speed, r_n = v0 / c,
  // and slides, r_t2 = -mu r_n (its relative velocity is up); the base
  // holds the rest of the vertical speed: r_n,base = (v0 + mu v0) / c.
  const double scale = v0 / c;
  EXPECT_NEAR(r[0], (1 + mu) * scale, 1e-8 * scale);
  EXPECT_NEAR(r[3], scale, 1e-8 * scale);
  EXPECT_NEAR(r[4], 0.0, 1e-8 * scale);
  EXPECT_NEAR(r[5], -mu * scale, 1e-8 * scale);
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
    const FrictionContactProblem3D p = rim_node();
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
