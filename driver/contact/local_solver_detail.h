#pragma once

#include "error.h"

#include <Eigen/Core>
#include <limits>

/// What the 2D and 3D exact local solvers (local_solver.cpp,
/// local_solver_3d.cpp) share: the residual they rank candidates by, the
/// fallback when rounding leaves no branch holding, and the cohesive shift.
namespace softpack::contact::detail
{

template <int D> using Vector = Eigen::Matrix<double, D, 1>;
template <int D> using Matrix = Eigen::Matrix<double, D, D>;

/// The squared natural-map residual of the reaction r of the local problem
/// u = W r + q (infinite for a reaction that is not finite)
template <int D>
double local_residual(const Matrix<D>& W, const Vector<D>& q, double mu,
                      const Vector<D>& r)
{
  if (!r.allFinite())
    return std::numeric_limits<double>::infinity();
  return natural_map_residual_squared(r, Vector<D>(W * r + q), mu);
}

/// Rounding at a branch boundary: the candidate with the smallest residual
/// once projected on the cone (so that the reaction stays admissible), or
/// separation when none does better; status ContactStatus::closest.
template <class Solution, int D, class Candidates>
Solution closest_candidate(const Matrix<D>& W, const Vector<D>& q, double mu,
                           const Candidates& candidates)
{
  Solution best{Vector<D>::Zero(), ContactStatus::closest};
  double best_res = local_residual<D>(W, q, mu, best.r);
  for (const Vector<D>& c : candidates)
  {
    const Vector<D> p = project_on_cone(c, mu);
    const double res = local_residual<D>(W, q, mu, p);
    if (res < best_res)
    {
      best_res = res;
      best.r = p;
    }
  }
  return best;
}

/// The cohesive local problem: the plain one for the shifted reaction
/// r' = r + c e_n, whose free velocity is q - c W e_n, shifted back; c = 0
/// is the plain problem itself (the same operations)
template <int D, class Solve>
auto solve_shifted(const Matrix<D>& W, const Vector<D>& q, double mu, double c,
                   Solve&& solve)
{
  if (c == 0)
    return solve(W, q, mu);
  auto s = solve(W, Vector<D>(q - c * W.col(0)), mu);
  s.r[0] -= c;
  return s;
}

} // namespace softpack::contact::detail
