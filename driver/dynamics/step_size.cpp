// The adaptive time step of the Moreau–Jean scheme (step_size.h).
#include "step_size.h"

#include "step_report.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{

StepSize::StepSize(double base, double largest, int hard_above_iterations)
    : _base(base), _largest(largest), _h(base),
      _hard_above(hard_above_iterations)
{
  if (!(base > 0) || !(largest >= base))
    throw std::invalid_argument(
        "StepSize: the largest step must be >= time.time_step > 0");
}

namespace
{
bool solved(const StepReport& report)
{
  return report.newton_converged && report.nlgs_converged &&
         report.unsolved_contact_solves == 0;
}
} // namespace

bool StepSize::needs_energy(const StepReport& report) const
{
  if (_largest == _base)
    return false;
  return !solved(report) || report.newton_iterations > _hard_above ||
         _calm_steps + 1 >= window;
}

StepSize::EnergyVerdict
StepSize::judge(const std::optional<WindowEnergy>& end) const
{
  if (!end)
    return EnergyVerdict::within;
  const double grown = std::abs(end->residual - _window_start.residual);
  const double supplied = std::abs(end->supplied - _window_start.supplied);
  if (!std::isfinite(grown) || !std::isfinite(supplied))
    return EnergyVerdict::unknown;
  return grown <= energy_tolerance * supplied ? EnergyVerdict::within
                                              : EnergyVerdict::beyond;
}

void StepSize::restart_window(const std::optional<WindowEnergy>& energy)
{
  _calm_steps = 0;
  _window_iterations = 0;
  // Without the accounts the next window's start is unknown: it is judged
  // by its iterations alone.
  const double unknown = std::nan("");
  _window_start = energy.value_or(WindowEnergy{unknown, unknown});
}

bool StepSize::update(const StepReport& report,
                      std::optional<WindowEnergy> energy)
{
  if (_largest == _base)
    return false;
  const double before = _h;
  if (!solved(report) || report.newton_iterations > _hard_above)
  {
    restart_window(energy);
    _h = std::max(_base, _h / 2);
    return _h != before;
  }
  ++_calm_steps;
  _window_iterations += report.newton_iterations;
  if (_calm_steps < window)
    return false;
  const double mean = static_cast<double>(_window_iterations) / window;
  const EnergyVerdict verdict = judge(energy);
  restart_window(energy);
  if (mean > shrink_above_iterations || verdict == EnergyVerdict::beyond)
    _h = std::max(_base, _h / 2);
  else if (mean <= grow_below_iterations && verdict == EnergyVerdict::within)
    _h = std::min(_largest, 2 * _h);
  return _h != before;
}

bool StepSize::retry()
{
  if (!can_retry())
    return false;
  _h = std::max(_base, _h / 2);
  // The window restarts; its energy start stays the last one read (the
  // accounts at this step's start are not read again): the next window is
  // judged over the steps since then.
  _calm_steps = 0;
  _window_iterations = 0;
  return true;
}

void StepSize::restore(const State& s)
{
  _h = s.h > 0 ? std::clamp(s.h, _base, _largest) : _base;
  _calm_steps = s.calm_steps;
  _window_iterations = s.window_iterations;
  _window_start = s.window_start;
}

} // namespace softpack::dynamics
