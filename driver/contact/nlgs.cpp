#include "nlgs.h"

#include "error.h"
#include "local_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
void check_arguments(const FrictionContactProblem2D& problem,
                     std::span<double> r, std::span<double> u,
                     const NlgsOptions& options)
{
  const std::size_t n = 2 * problem.num_contacts();
  if (!problem.W.finalized() or problem.W.num_contacts() != n / 2 or
      problem.q.size() != n)
    throw std::invalid_argument(
        "solve_nlgs: problem not validated (W, q, friction "
        "sizes or W not finalized)");
  if (r.size() != n or u.size() != n)
    throw std::invalid_argument("solve_nlgs: r and u need 2 per contact");
  if (!(options.relaxation > 0 and options.relaxation < 2))
    throw std::invalid_argument("solve_nlgs: relaxation must be in (0, 2)");
  if (!(options.tolerance >= 0) or options.max_sweeps < 0)
    throw std::invalid_argument("solve_nlgs: negative tolerance or sweeps");
}
//-----------------------------------------------------------------------------
/// One Gauss–Seidel sweep; returns the squared change of r and the squared
/// norm of the new r.
std::pair<double, double> sweep(const FrictionContactProblem2D& problem,
                                double* r, double omega)
{
  const DelassusMatrix& W = problem.W;
  const std::size_t nc = problem.num_contacts();
  double change = 0, norm = 0;
  for (std::size_t a = 0; a < nc; ++a)
  {
    const Eigen::Vector2d qa =
        Eigen::Vector2d(problem.q[2 * a], problem.q[2 * a + 1]) +
        W.offdiagonal_product(a, r);
    const double mu = problem.friction[a];
    Eigen::Vector2d ra = solve_local(W.diagonal(a), qa, mu).r;
    const Eigen::Vector2d old(r[2 * a], r[2 * a + 1]);
    if (omega != 1.0)
    {
      ra = omega * ra + (1.0 - omega) * old;
      if (omega > 1.0)
        ra = project_on_cone(ra, mu);
    }
    change += (ra - old).squaredNorm();
    norm += ra.squaredNorm();
    r[2 * a] = ra[0];
    r[2 * a + 1] = ra[1];
  }
  return {change, norm};
}
} // namespace

//-----------------------------------------------------------------------------
NlgsResult
softpack::contact::solve_nlgs(const FrictionContactProblem2D& problem,
                              std::span<double> r, std::span<double> u,
                              const NlgsOptions& options)
{
  check_arguments(problem, r, u, options);
  if (!options.warm_start)
    std::fill(r.begin(), r.end(), 0.0);

  NlgsResult result;
  result.q_zero = is_q_zero(problem, options.q_zero_tolerance);
  if (result.q_zero)
    std::fill(r.begin(), r.end(), 0.0);

  double working_tolerance = options.tolerance;
  bool full_error_current = false;
  NaturalMapError full;
  double omega = options.relaxation;
  double window_start_error = std::numeric_limits<double>::infinity();
  while (!result.q_zero and result.iterations < options.max_sweeps)
  {
    const auto [change, norm] = sweep(problem, r.data(), omega);
    ++result.iterations;
    const double scale = std::sqrt(norm);
    result.cheap_error = std::sqrt(change);
    if (scale > std::numeric_limits<double>::epsilon())
      result.cheap_error /= scale;
    full_error_current = false;
    if (!std::isfinite(result.cheap_error))
      break;
    if (omega != 1.0 and options.relaxation_window > 0 and
        result.iterations % options.relaxation_window == 0)
    {
      if (result.cheap_error > 0.9 * window_start_error)
      {
        omega = 1.0;
        result.relaxation_dropped = true;
      }
      window_start_error = result.cheap_error;
    }
    if (result.cheap_error > working_tolerance)
      continue;
    full = compute_error(problem, r, u, options.q_zero_tolerance);
    full_error_current = true;
    if (full.value <= options.tolerance)
      break;
    working_tolerance =
        full.value > 0 ? result.cheap_error / full.value * options.tolerance
                       : working_tolerance;
  }
  if (!full_error_current)
    full = compute_error(problem, r, u, options.q_zero_tolerance);
  result.error = full.value;
  result.converged = full.value <= options.tolerance;
  return result;
}
//-----------------------------------------------------------------------------
