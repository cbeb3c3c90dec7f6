#pragma once

namespace softpack::dynamics
{

struct StepReport;

/// The time step of each Moreau–Jean step: time.time_step throughout, or,
/// with time.max_step_factor above 1, a step adapted to how hard the steps
/// are (issue 17): doubled, up to max_step_factor x time_step, after
/// `window` steps that
/// all converged and needed on average at most `grow_below_iterations`
/// Newton iterations; halved, down to time_step, after a window that needed
/// more than `shrink_above_iterations` on average or a step that needed
/// more than time.refactor_above_iterations. A step whose Newton
/// iterations or contact solve fail is started again at half the size
/// (retry()), down to time_step. A quiet assembly (few, settled
/// contacts) then runs on long steps, a rearranging one on short ones; the
/// answers' invariance to the step is measured, not assumed
/// (docs/performance.md).
class StepSize
{
public:
  /// Steps judged together before a doubling
  static constexpr int window = 20;
  /// Mean Newton iterations of the window at or below which the step
  /// doubles: at 72 us the paper case needs 2.0-2.6 per step, at 144 us
  /// 2.6; cost per unit time ~ iterations / h, so a doubling pays while
  /// the iterations grow by less than that factor
  static constexpr double grow_below_iterations = 2.5;
  /// Mean Newton iterations of a window above which the step halves: the
  /// iterations then cost more than the longer step saves, and the energy
  /// balance closes less well (its quadrature error grows as h^2)
  static constexpr double shrink_above_iterations = 3.5;

  /// @param[in] base time.time_step, the smallest step (s)
  /// @param[in] largest time.max_step_factor x base (s, >= base; equal:
  /// fixed)
  /// @param[in] hard_above_iterations time.refactor_above_iterations
  StepSize(double base, double largest, int hard_above_iterations);

  /// The step to take next (s)
  double current() const { return _h; }

  /// Whether a step at the current size may be retried (retry() can
  /// succeed): above the base step only
  bool can_retry() const { return _h > _base; }

  /// A step could not be solved at the current size: halve it, down to the
  /// base, for a new attempt from the step's start.
  /// @return false at the base step (the step is then kept as it is, and
  /// counted as unsolved)
  bool retry();

  /// Account for a finished step.
  /// @return true if the step changed (the iteration matrix then no longer
  /// matches and must be refactorized)
  bool update(const StepReport& report);

  /// What a state file keeps: the current step and the window so far
  struct State
  {
    double h = 0;
    int calm_steps = 0;
    int window_iterations = 0;
  };
  State state() const { return {_h, _calm_steps, _window_iterations}; }
  /// Continue from a saved state (h = 0: the state predates adaptive steps;
  /// start from the base step)
  void restore(const State& s);

private:
  double _base, _largest, _h;
  int _hard_above;
  int _calm_steps = 0, _window_iterations = 0;
};

} // namespace softpack::dynamics
