// The adaptive time step's rule on reports made by hand: when it doubles,
// when it halves, its bounds, and its state.
#include <cmath>
#include <dynamics/moreau_jean.h>
#include <dynamics/step_size.h>
#include <gtest/gtest.h>

using softpack::dynamics::StepReport;
using softpack::dynamics::StepSize;

namespace
{
StepReport step(int newton_iterations, bool converged = true)
{
  StepReport r;
  r.newton_iterations = newton_iterations;
  r.newton_converged = converged;
  return r;
}

/// Feed `n` reports of `iterations` each; how many changed the step.
int feed(StepSize& s, int n, int iterations)
{
  int changes = 0;
  for (int k = 0; k < n; ++k)
    changes += s.update(step(iterations));
  return changes;
}
} // namespace

TEST(StepSize, FixedWhenTheLargestIsTheBase)
{
  StepSize s(1e-4, 1e-4, 5);
  EXPECT_EQ(feed(s, 100, 1), 0);
  EXPECT_FALSE(s.update(step(50, false)));
  EXPECT_EQ(s.current(), 1e-4);
}

TEST(StepSize, DoublesAfterACalmWindowUpToTheLargest)
{
  StepSize s(1e-4, 3e-4, 5);
  EXPECT_EQ(feed(s, StepSize::window - 1, 2), 0);
  EXPECT_TRUE(s.update(step(2)));
  EXPECT_EQ(s.current(), 2e-4);
  // The next window doubles again, capped at the largest step.
  EXPECT_EQ(feed(s, StepSize::window, 2), 1);
  EXPECT_EQ(s.current(), 3e-4);
  EXPECT_EQ(feed(s, 3 * StepSize::window, 1), 0);
  EXPECT_EQ(s.current(), 3e-4);
}

TEST(StepSize, AWindowAboveTheIterationThresholdKeepsTheStep)
{
  StepSize s(1e-4, 8e-4, 5);
  // Mean 3 > 2.5: no doubling, window after window.
  EXPECT_EQ(feed(s, 5 * StepSize::window, 3), 0);
  EXPECT_EQ(s.current(), 1e-4);
}

TEST(StepSize, HalvesAfterAWindowOfManyIterations)
{
  StepSize s(1e-4, 4e-4, 5);
  feed(s, 2 * StepSize::window, 2);
  ASSERT_EQ(s.current(), 4e-4);
  // Mean 4 > 3.5: halved at the end of the window, and again.
  EXPECT_EQ(feed(s, StepSize::window, 4), 1);
  EXPECT_EQ(s.current(), 2e-4);
  EXPECT_EQ(feed(s, 3 * StepSize::window, 4), 1);
  EXPECT_EQ(s.current(), 1e-4);
}

TEST(StepSize, HalvesAfterAHardOrUnsolvedStepDownToTheBase)
{
  StepSize s(1e-4, 8e-4, 5);
  feed(s, 3 * StepSize::window, 2);
  ASSERT_EQ(s.current(), 8e-4);
  EXPECT_FALSE(s.update(step(5))); // 5 is not above 5
  EXPECT_TRUE(s.update(step(6)));
  EXPECT_EQ(s.current(), 4e-4);
  EXPECT_TRUE(s.update(step(2, false))); // Newton unconverged
  EXPECT_EQ(s.current(), 2e-4);
  StepReport unsolved = step(2);
  unsolved.nlgs_converged = false;
  EXPECT_TRUE(s.update(unsolved));
  EXPECT_EQ(s.current(), 1e-4);
  EXPECT_FALSE(s.update(step(9)));
  EXPECT_EQ(s.current(), 1e-4);
  // A hard step also restarts the window.
  EXPECT_EQ(feed(s, StepSize::window - 1, 2), 0);
}

TEST(StepSize, StateRoundTripAndOldStates)
{
  StepSize a(1e-4, 8e-4, 5);
  feed(a, StepSize::window + 7, 2);
  StepSize b(1e-4, 8e-4, 5);
  b.restore(a.state());
  EXPECT_EQ(b.current(), a.current());
  // Both take their next doubling at the same step.
  for (int k = 0; k < 2 * StepSize::window; ++k)
    EXPECT_EQ(a.update(step(2)), b.update(step(2))) << k;
  // A state written before adaptive steps (h = 0) starts from the base.
  b.restore({});
  EXPECT_EQ(b.current(), 1e-4);
  EXPECT_THROW(StepSize(1e-4, 5e-5, 5), std::invalid_argument);
}

TEST(StepSize, RetryHalvesDownToTheBaseOnly)
{
  StepSize s(1e-4, 4e-4, 5);
  s.restore({4e-4, 7, 14});
  EXPECT_TRUE(s.can_retry());
  EXPECT_TRUE(s.retry());
  EXPECT_EQ(s.current(), 2e-4);
  // The window restarts: a doubling needs a whole calm window again.
  EXPECT_EQ(feed(s, StepSize::window - 1, 2), 0);
  s.restore({2e-4, 0, 0});
  EXPECT_TRUE(s.retry());
  EXPECT_EQ(s.current(), 1e-4);
  // At the base a step is kept as it is: MoreauJean::step keeps no copy
  // of its start then.
  EXPECT_FALSE(s.can_retry());
  EXPECT_FALSE(s.retry());
  EXPECT_EQ(s.current(), 1e-4);
  StepSize fixed(1e-4, 1e-4, 5);
  EXPECT_FALSE(fixed.can_retry());
  EXPECT_FALSE(fixed.retry());
}

namespace
{
/// Feed a window of calm steps (2 Newton iterations each) whose last step
/// reports the accounts `end`; whether the step changed.
bool window_ending_at(StepSize& s, StepSize::WindowEnergy end)
{
  for (int k = 0; k < StepSize::window - 1; ++k)
  {
    EXPECT_FALSE(s.needs_energy(step(2)));
    s.update(step(2));
  }
  EXPECT_TRUE(s.needs_energy(step(2)));
  return s.update(step(2), end);
}
} // namespace

TEST(StepSize, AWindowWhoseEnergyResidualGrewHalvesItAndKeepsItFromGrowing)
{
  const double tol = StepSize::energy_tolerance;
  StepSize s(1e-4, 8e-4, 5);
  // 1 J supplied, the residual grew by just under tol: the step doubles.
  EXPECT_TRUE(window_ending_at(s, {0.99 * tol, 1.0}));
  EXPECT_EQ(s.current(), 2e-4);
  // The next window supplies 1 J more and the residual grows by 2 tol: the
  // step halves although the iterations are few.
  EXPECT_TRUE(window_ending_at(s, {0.99 * tol + 2 * tol, 2.0}));
  EXPECT_EQ(s.current(), 1e-4);
  // At the base step a window beyond the tolerance keeps the base step.
  EXPECT_FALSE(window_ending_at(s, {1.0, 3.0}));
  EXPECT_EQ(s.current(), 1e-4);
  // Nothing supplied and nothing left over (bodies at rest): may grow.
  EXPECT_TRUE(window_ending_at(s, {1.0, 3.0}));
  EXPECT_EQ(s.current(), 2e-4);
  // A hard step asks for the accounts: the next window starts there.
  EXPECT_TRUE(s.needs_energy(step(9)));
  EXPECT_TRUE(s.update(step(9), StepSize::WindowEnergy{2.0, 4.0}));
  EXPECT_EQ(s.current(), 1e-4);
  EXPECT_FALSE(window_ending_at(s, {2.0 + 2 * tol, 5.0}));
  // At fixed steps the accounts are never asked for.
  StepSize fixed(1e-4, 1e-4, 5);
  EXPECT_FALSE(fixed.needs_energy(step(2)));
  EXPECT_FALSE(fixed.needs_energy(step(9)));
}

TEST(StepSize, AWindowStartedWithoutItsAccountsIsJudgedByIterationsAlone)
{
  // A state of layout 5 has no accounts at its window's start: that window
  // neither doubles nor halves on energy; the next one is judged again.
  StepSize s(1e-4, 8e-4, 5);
  StepSize::State old{2e-4, 0, 0};
  old.window_start = {std::nan(""), std::nan("")};
  s.restore(old);
  EXPECT_FALSE(window_ending_at(s, {1.0, 1.0}));
  EXPECT_EQ(s.current(), 2e-4);
  EXPECT_TRUE(window_ending_at(s, {1.0, 2.0}));
  EXPECT_EQ(s.current(), 4e-4);
}
