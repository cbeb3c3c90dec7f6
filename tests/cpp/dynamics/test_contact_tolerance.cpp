// The rule that gives a step's contact solves a smaller tolerance when its
// Newton iterations stall (ContactTolerance), on solves and rates made by
// hand. Its effect on runs: docs/contact_3d.md, "Newton and the contact
// solves' tolerance".
#include <dynamics/contact_tolerance.h>
#include <gtest/gtest.h>

using softpack::contact::NlgsResult;
using softpack::dynamics::ContactTolerance;
using softpack::dynamics::slow_rate;

namespace
{
constexpr double tolerance = 1e-6;

/// A solve given t.current() that ends with `error`
NlgsResult solve(const ContactTolerance& t, double error)
{
  NlgsResult r;
  r.error = error;
  r.converged = error <= t.current();
  return r;
}

/// Newton iteration k at rate rho, its solve reaching the tolerance it was
/// given (a tenth of it)
void iterate(ContactTolerance& t, int k, double rho)
{
  t.after_solve(solve(t, 0.1 * t.current()));
  t.after_iteration(k, rho);
}
} // namespace

TEST(ContactTolerance, StartsAtTheOption)
{
  ContactTolerance t(tolerance);
  EXPECT_EQ(t.current(), tolerance);
  EXPECT_TRUE(t.after_solve(solve(t, tolerance)));
  EXPECT_FALSE(t.after_solve(solve(t, 1.01 * tolerance)));
}

TEST(ContactTolerance, IterationsContractingAsNewtonKeepIt)
{
  ContactTolerance t(tolerance);
  const double rates[] = {1.0, 0.01, 0.2, 0.49, 0.1};
  for (int k = 0; k < 5; ++k)
    iterate(t, k, rates[k]);
  EXPECT_EQ(t.current(), tolerance);
}

TEST(ContactTolerance, OneSlowIterationAloneKeepsIt)
{
  // A slow rate then a fast one, again and again: never two in a row
  ContactTolerance t(tolerance);
  for (int k = 0; k < 20; ++k)
    iterate(t, k, k % 2 ? slow_rate : 0.1);
  EXPECT_EQ(t.current(), tolerance);
}

TEST(ContactTolerance, TheFirstIterationsRateIsNoStall)
{
  // Iteration 0 has no rate (the loop passes 1)
  ContactTolerance t(tolerance);
  iterate(t, 0, 1.0);
  iterate(t, 1, 0.99);
  EXPECT_EQ(t.current(), tolerance);
  iterate(t, 2, 0.99);
  EXPECT_DOUBLE_EQ(t.current(), tolerance / ContactTolerance::cut);
}

TEST(ContactTolerance, TwoStallsCutItAndTheCountStartsAgain)
{
  ContactTolerance t(tolerance);
  iterate(t, 0, 1.0);
  iterate(t, 1, 0.995);
  iterate(t, 2, 0.995);
  EXPECT_DOUBLE_EQ(t.current(), tolerance / 100);
  // The rate right after a cut measures the cut (here a jump): one stall
  iterate(t, 3, 25.0);
  EXPECT_DOUBLE_EQ(t.current(), tolerance / 100);
  iterate(t, 4, 0.9);
  EXPECT_DOUBLE_EQ(t.current(), tolerance / 1e4);
}

TEST(ContactTolerance, NeverBelowItsFloor)
{
  ContactTolerance t(tolerance);
  for (int k = 0; k < 40; ++k)
    iterate(t, k, k > 0 ? 0.99 : 1.0);
  EXPECT_DOUBLE_EQ(t.current(),
                   tolerance * ContactTolerance::smallest_fraction);
}

TEST(ContactTolerance, ASolveThatMissesACutToleranceEndsTheCuts)
{
  ContactTolerance t(tolerance);
  iterate(t, 0, 1.0);
  iterate(t, 1, 0.99);
  iterate(t, 2, 0.99); // cut to 1e-8, which the next solve meets
  iterate(t, 3, 0.99);
  iterate(t, 4, 0.99); // cut to 1e-10
  ASSERT_DOUBLE_EQ(t.current(), tolerance / 1e4);
  // Its solve stops at its sweeps with 3e-9: converged (the option's
  // tolerance met), the tolerance back to the last one met, no more cuts
  EXPECT_TRUE(t.after_solve(solve(t, 3e-9)));
  EXPECT_DOUBLE_EQ(t.current(), tolerance / 100);
  for (int k = 5; k < 20; ++k)
    iterate(t, k, 0.99);
  EXPECT_DOUBLE_EQ(t.current(), tolerance / 100);
}

TEST(ContactTolerance, AnUnconvergedSolveIsNoStallOfItsOwn)
{
  // A solve that missed the option's tolerance is reported as such; a
  // smaller tolerance would not help it; and it breaks a run of stalls
  ContactTolerance t(tolerance);
  for (int k = 0; k < 10; ++k)
  {
    EXPECT_FALSE(t.after_solve(solve(t, 2 * tolerance)));
    t.after_iteration(k, 0.99);
  }
  EXPECT_EQ(t.current(), tolerance);
  iterate(t, 10, 0.99);
  t.after_solve(solve(t, 2 * tolerance));
  t.after_iteration(11, 0.99);
  iterate(t, 12, 0.99);
  EXPECT_EQ(t.current(), tolerance);
}
