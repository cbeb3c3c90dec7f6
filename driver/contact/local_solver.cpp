#include "local_solver.h"

#include "error.h"
#include "local_solver_detail.h"

#include <array>
#include <cmath>
#include <limits>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
/// Stick: solve W r = -q; valid when r lies in the cone.
bool try_stick(const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu,
               Eigen::Vector2d& r)
{
  const double det = W(0, 0) * W(1, 1) - W(0, 1) * W(1, 0);
  if (!(std::abs(det) > 0))
    return false;
  r[0] = -(W(1, 1) * q[0] - W(0, 1) * q[1]) / det;
  r[1] = -(W(0, 0) * q[1] - W(1, 0) * q[0]) / det;
  return r.allFinite() and r[0] >= 0 and std::abs(r[1]) <= mu * r[0];
}
//-----------------------------------------------------------------------------
/// Slide with sign(u_t) = s: r = r_n (1, -s mu), u_n = 0; valid when
/// r_n >= 0 and s u_t >= 0.
bool try_slide(const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu,
               double s, Eigen::Vector2d& r)
{
  const double g = W(0, 0) - s * mu * W(0, 1);
  if (!(g > 0))
    return false;
  const double rn = -q[0] / g;
  r = {rn, -s * mu * rn};
  const double ut = (W(1, 0) - s * mu * W(1, 1)) * rn + q[1];
  return std::isfinite(rn) and rn >= 0 and s * ut >= 0;
}
} // namespace

//-----------------------------------------------------------------------------
LocalSolution softpack::contact::solve_local(const Eigen::Matrix2d& W,
                                             const Eigen::Vector2d& q,
                                             double mu)
{
  if (q[0] >= 0)
    return {Eigen::Vector2d::Zero(), ContactStatus::separated};

  std::array<Eigen::Vector2d, 3> candidate;
  candidate.fill(Eigen::Vector2d::Zero());
  if (try_stick(W, q, mu, candidate[0]))
    return {candidate[0], ContactStatus::stick};
  if (try_slide(W, q, mu, 1.0, candidate[1]))
    return {candidate[1], ContactStatus::slide_positive};
  if (try_slide(W, q, mu, -1.0, candidate[2]))
    return {candidate[2], ContactStatus::slide_negative};

  return detail::closest_candidate<LocalSolution, 2>(W, q, mu, candidate);
}
//-----------------------------------------------------------------------------
LocalSolution softpack::contact::solve_local(const Eigen::Matrix2d& W,
                                             const Eigen::Vector2d& q,
                                             double mu, double c)
{
  return detail::solve_shifted<2>(
      W, q, mu, c,
      [](const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu)
      { return solve_local(W, q, mu); });
}
//-----------------------------------------------------------------------------
