#pragma once

#include <limits>
#include <optional>

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
/// (retry()), down to time_step. A window is also judged by the energy
/// balance: it doubles only if the residual grew over the window by at most
/// `energy_tolerance` of the energy supplied over it, and halves if it grew
/// by more. A quiet assembly (few, settled contacts) then runs on long
/// steps, a rearranging one or one of fast impacts on short ones; the
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
  /// Largest growth of the energy residual over a window, as a fraction of
  /// the energy supplied over it (wall and external work), at which the
  /// step may double: the residual's part from long steps then stays below
  /// this fraction of the work. Measured: a quasi-static compaction (the
  /// paper case) closes its balance to ~1e-6 of the work at every step
  /// size, disks flying into each other (tests/python/test_fuzz.py) to
  /// 6e-5-6e-4 at their base step and up to 1.03e-3 at a factor of 2
  static constexpr double energy_tolerance = 1e-4;

  /// The energy accounts a window is judged by
  struct WindowEnergy
  {
    double residual; ///< EnergyBalance::residual()
    double supplied; ///< wall_work + external_work
  };

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

  /// Whether update() for this finished step wants the energy accounts
  /// after it (a window ends or restarts there; never at fixed steps)
  bool needs_energy(const StepReport& report) const;

  /// Account for a finished step.
  /// @param[in] report The step's report
  /// @param[in] energy The accounts after the step when needs_energy()
  /// (absent: the window is judged by its Newton iterations alone)
  /// @return true if the step changed (the iteration matrix then no longer
  /// matches and must be refactorized)
  bool update(const StepReport& report,
              std::optional<WindowEnergy> energy = std::nullopt);

  /// What a state file keeps: the current step and the window so far
  struct State
  {
    double h = 0;
    int calm_steps = 0;
    int window_iterations = 0;
    /// The accounts at the window's start (NaN: unknown, the window is not
    /// judged by energy)
    WindowEnergy window_start = {std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::quiet_NaN()};
  };
  State state() const
  {
    return {_h, _calm_steps, _window_iterations, _window_start};
  }
  /// Continue from a saved state (h = 0: the state predates adaptive steps;
  /// start from the base step)
  void restore(const State& s);

private:
  /// How the window's energy residual grew against the energy supplied
  enum class EnergyVerdict
  {
    within,
    beyond,
    unknown
  };
  EnergyVerdict judge(const std::optional<WindowEnergy>& end) const;
  /// A new window starts after this step
  void restart_window(const std::optional<WindowEnergy>& energy);

  double _base, _largest, _h;
  int _hard_above;
  int _calm_steps = 0, _window_iterations = 0;
  /// The accounts at a run's start: nothing supplied, nothing left over
  WindowEnergy _window_start = {0, 0};
};

} // namespace softpack::dynamics
