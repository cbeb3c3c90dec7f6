#pragma once

// A contact problem solved from zero reactions by the NLGS, as the law tests
// (cohesive, bonded) run it on the FCLIB set and on hand-made problems.

#include "nlgs.h"
#include "problem.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <vector>

namespace softpack::contact::test
{

/// Reactions, velocities and the solver's outcome
struct Solve
{
  std::vector<double> r, u;
  NlgsResult result;
};

inline Solve solve(const FrictionContactProblem2D& p, const NlgsOptions& opt)
{
  Solve s{std::vector<double>(2 * p.num_contacts(), 0.0),
          std::vector<double>(2 * p.num_contacts()),
          {}};
  s.result = solve_nlgs(p, s.r, s.u, opt);
  return s;
}

/// The options of the simulator (over-relaxed, alternate order) or plain
/// Gauss–Seidel (relaxation 1, contact order)
inline NlgsOptions options(double tolerance, double relaxation,
                           int max_sweeps = 10000)
{
  NlgsOptions opt;
  opt.tolerance = tolerance;
  opt.max_sweeps = max_sweeps;
  opt.relaxation = relaxation;
  opt.order = relaxation == 1.0 ? SweepOrder::contact : SweepOrder::alternate;
  return opt;
}

/// `other` solves as `plain` does, bit for bit, under both relaxations
/// (the laws' zero cases: no cohesion, no bond)
inline void expect_the_same_solves(const FrictionContactProblem2D& plain,
                                   const FrictionContactProblem2D& other,
                                   double tolerance, int max_sweeps = 10000)
{
  for (double relaxation : {1.0, 1.7})
  {
    const NlgsOptions opt = options(tolerance, relaxation, max_sweeps);
    const Solve a = solve(plain, opt), b = solve(other, opt);
    EXPECT_EQ(a.result.iterations, b.result.iterations);
    EXPECT_EQ(a.result.error, b.result.error);
    EXPECT_EQ(a.r, b.r);
    EXPECT_EQ(a.u, b.u);
  }
}

/// The largest |q_i| of a problem: the scale of its impulses
inline double largest_free_velocity(const FrictionContactProblem2D& p)
{
  double q_max = 0;
  for (double v : p.q)
    q_max = std::max(q_max, std::abs(v));
  return q_max;
}

} // namespace softpack::contact::test
