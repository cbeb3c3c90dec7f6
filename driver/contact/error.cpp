#include "error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

using namespace softpack::contact;

//-----------------------------------------------------------------------------
Eigen::Vector2d softpack::contact::project_on_cone(const Eigen::Vector2d& x,
                                                   double mu)
{
  const double xn = x[0];
  const double abs_t = std::abs(x[1]);
  if (mu * abs_t <= -xn)
    return Eigen::Vector2d::Zero(); // in the polar cone
  if (abs_t <= mu * xn)
    return x; // inside K
  const double pn = (xn + mu * abs_t) / (1.0 + mu * mu);
  return {pn, std::copysign(mu * pn, x[1])};
}
//-----------------------------------------------------------------------------
double softpack::contact::natural_map_residual_squared(const Eigen::Vector2d& r,
                                                       const Eigen::Vector2d& u,
                                                       double mu)
{
  const Eigen::Vector2d u_desaxce(u[0] + mu * std::abs(u[1]), u[1]);
  return (r - project_on_cone(r - u_desaxce, mu)).squaredNorm();
}
//-----------------------------------------------------------------------------
bool softpack::contact::is_q_zero(const FrictionContactProblem2D& problem,
                                  double q_zero_tolerance)
{
  return std::all_of(problem.q.begin(), problem.q.end(),
                     [q_zero_tolerance](double v)
                     { return std::abs(v) <= q_zero_tolerance; });
}
//-----------------------------------------------------------------------------
namespace
{
/// Contact a's terms of the ErrorSums, its u_a written
void add_contact(ErrorSums& sums, const FrictionContactProblem2D& problem,
                 std::span<const double> r, std::span<double> u, std::size_t a)
{
  const Eigen::Vector2d qa(problem.q[2 * a], problem.q[2 * a + 1]);
  const Eigen::Vector2d ua = qa + problem.W.row_product(a, r.data());
  u[2 * a] = ua[0];
  u[2 * a + 1] = ua[1];
  const Eigen::Vector2d ra(r[2 * a], r[2 * a + 1]);
  sums.residual += natural_map_residual_squared(
      shifted_reaction(ra, problem.cohesion_of(a)), ua, problem.friction[a]);
  sums.r += ra.squaredNorm();
  sums.u += ua.squaredNorm();
  sums.q += qa.squaredNorm();
}

void check_sizes(const FrictionContactProblem2D& problem,
                 std::span<const double> r, std::span<double> u)
{
  const std::size_t nc = problem.num_contacts();
  if (r.size() != 2 * nc or u.size() != 2 * nc)
    throw std::invalid_argument("compute_error: r and u need 2 per contact");
}
} // namespace
//-----------------------------------------------------------------------------
ErrorSums softpack::contact::error_sums(const FrictionContactProblem2D& problem,
                                        std::span<const double> r,
                                        std::span<double> u,
                                        std::span<const std::int32_t> rows)
{
  check_sizes(problem, r, u);
  ErrorSums sums;
  for (const std::int32_t a : rows)
    add_contact(sums, problem, r, u, static_cast<std::size_t>(a));
  return sums;
}
//-----------------------------------------------------------------------------
NaturalMapError softpack::contact::natural_map_error(const ErrorSums& sums,
                                                     bool q_zero)
{
  NaturalMapError e;
  e.absolute = std::sqrt(sums.residual);
  e.scale = std::sqrt(std::max({sums.r, sums.u, sums.q}));
  e.q_zero = q_zero;
  if (e.q_zero or e.scale <= std::numeric_limits<double>::epsilon())
    e.value = e.absolute;
  else
    e.value = e.absolute / e.scale;
  return e;
}
//-----------------------------------------------------------------------------
NaturalMapError
softpack::contact::compute_error(const FrictionContactProblem2D& problem,
                                 std::span<const double> r, std::span<double> u,
                                 double q_zero_tolerance)
{
  check_sizes(problem, r, u);
  ErrorSums sums;
  for (std::size_t a = 0; a < problem.num_contacts(); ++a)
    add_contact(sums, problem, r, u, a);
  return natural_map_error(sums, is_q_zero(problem, q_zero_tolerance));
}
//-----------------------------------------------------------------------------
