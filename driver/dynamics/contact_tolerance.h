#pragma once
// The tolerance of the contact solves within one step's Newton iterations.
#include <algorithm>
#include <contact/nlgs.h>

namespace softpack::dynamics
{

/// Newton iterations contracting slower than this rate do not converge as
/// Newton does (a modified Newton on a step's smooth part contracts at
/// 0.001-0.2): their error is not estimated from the rate (NewtonLoop), and
/// twice in a row they have stalled (ContactTolerance).
inline constexpr double slow_rate = 0.5;

/// The tolerance given to each contact solve of one step's Newton
/// iterations: contact.nlgs_tolerance, cut when the iterations stall after
/// converged solves.
///
/// Such a stall is the solves' inexactness. Their relative natural-map
/// error mixes impulses with velocities and is scaled by max(|r|, |u|,
/// |q|), which the open contacts' gap / h inflate, so that a solve within
/// its tolerance can leave a velocity off by more than Newton's tolerance;
/// and each solve, warm-started from the last, stops at its first check.
/// The iterations then crawl at the solver's own slow rate, and end
/// unconverged at time.newton_max_iterations (docs/contact_3d.md, "Newton
/// and the contact solves' tolerance"). A smaller tolerance makes the next
/// solves sweep on.
class ContactTolerance
{
public:
  /// Iterations stalled in a row before a cut (one alone may precede a fast
  /// contraction), counted again after each cut
  static constexpr int stalls_before_cut = 2;
  /// Each cut divides the tolerance by this
  static constexpr double cut = 100;
  /// ... down to contact.nlgs_tolerance times this (two cuts)
  static constexpr double smallest_fraction = 1e-4;

  /// @param[in] tolerance contact.nlgs_tolerance
  explicit ContactTolerance(double tolerance)
      : _tolerance(tolerance), _current(tolerance), _reached(tolerance)
  {
  }

  /// The tolerance of the next solve
  double current() const { return _current; }

  /// Take a solve's outcome; returns whether it has converged: its error
  /// meets contact.nlgs_tolerance, whatever the tolerance it was given. A
  /// solve that missed a cut tolerance within contact.nlgs_max_sweeps
  /// (while meeting the option's) ends the cuts of the step: the next
  /// solves are given the last tolerance a solve met, so that no further
  /// solve spends its whole sweeps on a target out of its reach.
  bool after_solve(const contact::NlgsResult& nlgs)
  {
    _converged = nlgs.converged || nlgs.error <= _tolerance;
    if (nlgs.converged)
      _reached = std::min(_reached, _current);
    else if (_converged)
    {
      _current = _reached;
      _cuts_ended = true;
    }
    return _converged;
  }

  /// After Newton iteration k, which contracted at rate rho (its solve
  /// taken by after_solve)
  void after_iteration(int k, double rho)
  {
    if (_cuts_ended)
      return;
    _stalled = k > 0 && rho >= slow_rate && _converged ? _stalled + 1 : 0;
    if (_stalled < stalls_before_cut)
      return;
    _current = std::max(_current / cut, _tolerance * smallest_fraction);
    _stalled = 0;
  }

private:
  double _tolerance;
  double _current;
  /// The smallest tolerance a solve of the step has met
  double _reached;
  /// The last solve converged (after_solve)
  bool _converged = true;
  bool _cuts_ended = false;
  int _stalled = 0;
};

} // namespace softpack::dynamics
