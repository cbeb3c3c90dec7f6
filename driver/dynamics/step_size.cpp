// The adaptive time step of the Moreau–Jean scheme (step_size.h).
#include "step_size.h"

#include "step_report.h"

#include <algorithm>
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

bool StepSize::update(const StepReport& report)
{
  if (_largest == _base)
    return false;
  const bool solved = report.newton_converged && report.nlgs_converged &&
                      report.unsolved_contact_solves == 0;
  if (!solved || report.newton_iterations > _hard_above)
  {
    _calm_steps = 0;
    _window_iterations = 0;
    const double before = _h;
    _h = std::max(_base, _h / 2);
    return _h != before;
  }
  ++_calm_steps;
  _window_iterations += report.newton_iterations;
  if (_calm_steps < window)
    return false;
  const double mean = static_cast<double>(_window_iterations) / window;
  _calm_steps = 0;
  _window_iterations = 0;
  const double before = _h;
  if (mean > shrink_above_iterations)
    _h = std::max(_base, _h / 2);
  else if (mean <= grow_below_iterations)
    _h = std::min(_largest, 2 * _h);
  return _h != before;
}

bool StepSize::retry()
{
  if (!can_retry())
    return false;
  _h = std::max(_base, _h / 2);
  _calm_steps = 0;
  _window_iterations = 0;
  return true;
}

void StepSize::restore(const State& s)
{
  _h = s.h > 0 ? std::clamp(s.h, _base, _largest) : _base;
  _calm_steps = s.calm_steps;
  _window_iterations = s.window_iterations;
}

} // namespace softpack::dynamics
