#pragma once

#include "error.h"
#include "problem.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace softpack::contact
{

/// Moves Gauss–Seidel's reactions along a constant drift to where it ends
/// (NlgsOptions::extrapolate).
///
/// Where W is singular in a direction the law leaves free, the problem's
/// solutions form a segment and Gauss–Seidel creeps along it by the same
/// change every sweep until a contact reaches the edge of its cone. In a
/// standing packing a node of a cylinder's bottom rim touches both the
/// frictionless base and a neighbour: the base's normal reaction and the
/// neighbour's vertical friction act on the same node in the same
/// direction, so only their difference moves it, and a small conflict
/// between the two contacts' target velocities makes both grow by about
/// 1e-9 N s a sweep until the friction saturates, hundreds of sweeps later
/// (docs/performance_3d.md, "Gauss–Seidel's drift"). When two successive
/// sweeps changed r by the same vector d (within `tolerance` of |d|), r is
/// moved to r + t d with the largest t that keeps every contact in its
/// cone (shifted by its cohesion), if t is at least `min_step` sweeps and
/// at most `max_step`; then the sweeps go on. The answer is still the one
/// the error test accepts: only the path to it is shortened.
///
/// Not every constant change is such a drift: a slowly contracting sweep
/// also changes r by nearly the same vector twice, and following it up to
/// max_step sweeps lands far from the answer. So a jump is kept only if
/// the natural-map error after it is at most `max_error_rise` times the
/// error before; otherwise r is put back and the sweeps go on.
template <int D> class DriftExtrapolation
{
public:
  /// Relative difference of two successive changes below which they are
  /// one drift
  static constexpr double tolerance = 1e-2;
  /// Shorter extrapolations are left to the sweeps
  static constexpr double min_step = 2;
  /// A drift that no cone stops is not followed further than this
  static constexpr double max_step = 1e4;
  /// A jump that multiplies the natural-map error by more than this is
  /// undone: at the end of a drift the error is what it was within 1 %
  /// (the creeping pairs' residual leaves with the next sweeps), where a
  /// slowly contracting sweep followed to max_step multiplies it by 1.3 to
  /// 1e5 (the plane-strain slab's problems at 1e-8, docs/performance_3d.md)
  static constexpr double max_error_rise = 1.1;

  /// @param[in] problem Its friction and cohesion (in the numbering of the
  ///   reactions given to after_sweep()), kept by reference
  explicit DriftExtrapolation(const FrictionContactProblem<D>& problem)
      : _problem(problem)
  {
  }

  /// After a sweep: move r if the last two sweeps drifted.
  /// @param[in,out] r Reactions, D per contact
  /// @return true if r was moved (the caller remakes what it derived
  ///   from r: velocities, rank-one sums)
  bool after_sweep(std::span<double> r)
  {
    if (_previous.size() != r.size())
    {
      _previous.assign(r.begin(), r.end());
      _change.clear();
      return false;
    }
    double difference = 0, length = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
    {
      const double d = r[i] - _previous[i];
      if (!_change.empty())
        difference += (d - _change[i]) * (d - _change[i]);
      length += d * d;
    }
    const bool drift = !_change.empty() and length > 0 and
                       difference <= tolerance * tolerance * length;
    _change.resize(r.size());
    for (std::size_t i = 0; i < r.size(); ++i)
    {
      _change[i] = r[i] - _previous[i];
      _previous[i] = r[i];
    }
    if (!drift)
      return false;
    const double t = step(r);
    if (!(t >= min_step))
      return false;
    const bool kept = jump(r, t);
    _previous.clear();
    _change.clear();
    return kept;
  }

  /// @return The extrapolations made (and kept) so far
  int extrapolations() const { return _extrapolations; }
  /// @return The jumps undone so far (max_error_rise)
  int undone() const { return _undone; }

private:
  /// r moved by t times the drift, kept if the error allows it
  /// (max_error_rise), else put back
  /// @return true if r was moved
  bool jump(std::span<double> r, double t)
  {
    _before.assign(r.begin(), r.end());
    _u.resize(r.size());
    const double before = compute_error(_problem, r, _u, 0).value;
    for (std::size_t i = 0; i < r.size(); ++i)
      r[i] += t * _change[i];
    project(r);
    if (compute_error(_problem, r, _u, 0).value <= max_error_rise * before)
    {
      ++_extrapolations;
      return true;
    }
    std::copy(_before.begin(), _before.end(), r.begin());
    ++_undone;
    return false;
  }

  /// The largest t (at most max_step) for which r + t d stays in every
  /// contact's cone
  double step(std::span<const double> r) const
  {
    double t = max_step;
    for (std::size_t a = 0; a < _problem.num_contacts(); ++a)
    {
      const double* ra = r.data() + D * a;
      const double* da = _change.data() + D * a;
      const double rn = ra[0] + _problem.cohesion_of(a), dn = da[0];
      if (dn < 0)
        t = std::min(t, -rn / dn);
      // |r_t + s d_t|^2 - mu^2 (r_n + s d_n)^2 = A s^2 + B s + C, C <= 0
      const double mu = _problem.friction[a];
      double A = -mu * mu * dn * dn, B = -2 * mu * mu * rn * dn,
             C = -mu * mu * rn * rn;
      for (int j = 1; j < D; ++j)
      {
        A += da[j] * da[j];
        B += 2 * ra[j] * da[j];
        C += ra[j] * ra[j];
      }
      t = std::min(t, first_positive_root(A, B, C));
    }
    return t;
  }

  /// The smallest root of A s^2 + B s + C above a millionth of a sweep
  /// (infinity if none): roots nearer 0 are contacts that slide along
  /// their cone's surface, which project() keeps on it
  static double first_positive_root(double A, double B, double C)
  {
    constexpr double floor = 1e-6;
    double s = std::numeric_limits<double>::infinity();
    if (A == 0)
    {
      if (B != 0 and -C / B > floor)
        s = -C / B;
      return s;
    }
    const double discriminant = B * B - 4 * A * C;
    if (discriminant < 0)
      return s;
    const double root = std::sqrt(discriminant);
    for (const double x : {(-B - root) / (2 * A), (-B + root) / (2 * A)})
      if (x > floor)
        s = std::min(s, x);
    return s;
  }

  /// Each reaction onto its (shifted) cone: the extrapolation's rounding
  /// and the contacts sliding along the cone's surface
  void project(std::span<double> r) const
  {
    using Vector = Eigen::Matrix<double, D, 1>;
    for (std::size_t a = 0; a < _problem.num_contacts(); ++a)
    {
      Eigen::Map<Vector> ra(r.data() + D * a);
      const double c = _problem.cohesion_of(a);
      const Vector shifted = shifted_reaction<D>(Vector(ra), c);
      ra = project_on_cone(shifted, _problem.friction[a]) - c * Vector::Unit(0);
    }
  }

  const FrictionContactProblem<D>& _problem;
  std::vector<double> _previous, _change;
  /// r before a jump and the velocities of the errors, kept to reuse
  std::vector<double> _before, _u;
  int _extrapolations = 0, _undone = 0;
};

} // namespace softpack::contact
