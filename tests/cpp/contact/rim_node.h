#pragma once
// The rim node: one node touching a frictionless base and a rigid
// neighbour with friction, whose answer is known by hand (the drift tests
// and the condensation tests solve it).
#include "problem.h"

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <span>

namespace softpack::contact::rim_node
{
constexpr double c = 1e5;     // the node's compliance, isotropic (m/s per N s)
constexpr double mu = 0.3;    // the neighbour's friction
constexpr double v0 = 0.1;    // the node's free speed into the neighbour (m/s)
constexpr double slip = 1e-5; // the neighbour's vertical speed (m/s)

/// Contact 0: the base, normal z; contact 1: the neighbour, normal x, its
/// second tangent z. Both act on one node of compliance c I, so W is
/// [R_a^T; R_b^T] c [R_a R_b], of rank 3: the base's normal reaction and
/// the neighbour's vertical friction move the node alike. The node's free
/// velocity is (-v0, 0, base_speed) (base_speed < 0: into the base); the
/// neighbour moves down by `slip` relative to the base. With `free_node`,
/// a third contact (friction mu) on a node of its own, its free velocity
/// -v0 along its normal, keeps a problem without the first two non-empty.
inline FrictionContactProblem3D problem(double base_speed = -v0,
                                        bool free_node = false)
{
  Eigen::Matrix3d Ra, Rb; // columns n, t1, t2 in world components
  Ra << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  Rb << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  const Eigen::Matrix3d C = c * Eigen::Matrix3d::Identity();
  FrictionContactProblem3D p;
  p.W = DelassusMatrix3D(free_node ? 3 : 2);
  p.W.add_block(0, 0, Ra.transpose() * C * Ra);
  p.W.add_block(1, 1, Rb.transpose() * C * Rb);
  p.W.add_block(0, 1, Ra.transpose() * C * Rb);
  p.W.add_block(1, 0, Rb.transpose() * C * Ra);
  if (free_node)
    p.W.add_block(2, 2, C);
  p.W.finalize();
  const Eigen::Vector3d v(-v0, 0, base_speed);
  const Eigen::Vector3d qa = Ra.transpose() * v;
  Eigen::Vector3d qb = Rb.transpose() * v;
  qb[2] += slip;
  p.q = {qa[0], qa[1], qa[2], qb[0], qb[1], qb[2]};
  p.friction = {0.0, mu};
  if (free_node)
  {
    p.q.insert(p.q.end(), {-v0, 0, 0});
    p.friction.push_back(mu);
  }
  validate(p);
  return p;
}

/// The answer by hand, within `relative` of v0 / c: the neighbour holds the
/// node's horizontal speed, r_n = v0 / c, and slides, r_t2 = -mu r_n (its
/// relative velocity is up); the base holds the rest of the vertical
/// speed, r_n,base = (1 + mu) v0 / c
inline void expect_answer(std::span<const double> r, double relative)
{
  const double scale = v0 / c;
  EXPECT_NEAR(r[0], (1 + mu) * scale, relative * scale);
  EXPECT_NEAR(r[3], scale, relative * scale);
  EXPECT_NEAR(r[4], 0.0, relative * scale);
  EXPECT_NEAR(r[5], -mu * scale, relative * scale);
}
} // namespace softpack::contact::rim_node
