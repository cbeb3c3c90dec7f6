#include "error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

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
template <>
Eigen::Vector3d softpack::contact::project_on_cone<3>(const Eigen::Vector3d& x,
                                                      double mu)
{
  const double xn = x[0];
  const double abs_t = std::sqrt(x[1] * x[1] + x[2] * x[2]);
  if (mu * abs_t <= -xn)
    return Eigen::Vector3d::Zero(); // in the polar cone
  if (abs_t <= mu * xn)
    return x; // inside K
  // (abs_t > 0 here: abs_t = 0 is inside K or in its polar cone)
  const double pn = (xn + mu * abs_t) / (1.0 + mu * mu);
  const double scale = mu * pn / abs_t;
  return {pn, scale * x[1], scale * x[2]};
}
//-----------------------------------------------------------------------------
template <>
double softpack::contact::natural_map_residual_squared<3>(
    const Eigen::Vector3d& r, const Eigen::Vector3d& u, double mu)
{
  const Eigen::Vector3d u_desaxce(
      u[0] + mu * std::sqrt(u[1] * u[1] + u[2] * u[2]), u[1], u[2]);
  return (r - project_on_cone(Eigen::Vector3d(r - u_desaxce), mu))
      .squaredNorm();
}
//-----------------------------------------------------------------------------
double softpack::contact::natural_map_residual_squared(const Eigen::Vector2d& r,
                                                       const Eigen::Vector2d& u,
                                                       double mu)
{
  const Eigen::Vector2d u_desaxce(u[0] + mu * std::abs(u[1]), u[1]);
  return (r - project_on_cone(Eigen::Vector2d(r - u_desaxce), mu))
      .squaredNorm();
}
//-----------------------------------------------------------------------------
namespace
{
template <int D>
bool q_is_zero(const FrictionContactProblem<D>& problem,
               double q_zero_tolerance)
{
  return std::all_of(problem.q.begin(), problem.q.end(),
                     [q_zero_tolerance](double v)
                     { return std::abs(v) <= q_zero_tolerance; });
}
//-----------------------------------------------------------------------------
/// W's rank-one terms' sums at r (DelassusMatrix::rank_one_sums): u sees
/// the whole W
template <int D>
std::vector<double> term_sums(const FrictionContactProblem<D>& problem,
                              std::span<const double> r)
{
  std::vector<double> terms(problem.W.rank_one_terms().size());
  problem.W.rank_one_sums(r.data(), terms.data());
  return terms;
}
//-----------------------------------------------------------------------------
/// Contact a's terms of the ErrorSums, its u_a written (`terms`: the
/// rank-one terms' sums, empty when W has none)
template <int D>
void add_contact(ErrorSums& sums, const FrictionContactProblem<D>& problem,
                 std::span<const double> r, std::span<double> u, std::size_t a,
                 const std::vector<double>& terms)
{
  using Vector = Eigen::Matrix<double, D, 1>;
  const Vector qa = contact_vector<D>(problem.q.data(), a);
  const Vector ua =
      qa + problem.W.row_product(a, r.data(),
                                 terms.empty() ? nullptr : terms.data());
  for (int j = 0; j < D; ++j)
    u[D * a + j] = ua[j];
  const Vector ra = contact_vector<D>(r.data(), a);
  sums.residual += natural_map_residual_squared(
      shifted_reaction(ra, problem.cohesion_of(a)), ua, problem.friction[a]);
  sums.r += ra.squaredNorm();
  sums.u += ua.squaredNorm();
  sums.q += qa.squaredNorm();
}

template <int D>
void check_sizes(const FrictionContactProblem<D>& problem,
                 std::span<const double> r, std::span<double> u)
{
  const std::size_t nc = problem.num_contacts();
  if (r.size() != D * nc or u.size() != D * nc)
    throw std::invalid_argument("compute_error: r and u need " +
                                std::to_string(D) + " per contact");
}
//-----------------------------------------------------------------------------
template <int D>
ErrorSums sums_over(const FrictionContactProblem<D>& problem,
                    std::span<const double> r, std::span<double> u,
                    std::span<const std::int32_t> rows)
{
  check_sizes(problem, r, u);
  const std::vector<double> terms = term_sums(problem, r);
  ErrorSums sums;
  for (const std::int32_t a : rows)
    add_contact(sums, problem, r, u, static_cast<std::size_t>(a), terms);
  return sums;
}
//-----------------------------------------------------------------------------
template <int D>
NaturalMapError full_error(const FrictionContactProblem<D>& problem,
                           std::span<const double> r, std::span<double> u,
                           double q_zero_tolerance)
{
  check_sizes(problem, r, u);
  const std::vector<double> terms = term_sums(problem, r);
  ErrorSums sums;
  for (std::size_t a = 0; a < problem.num_contacts(); ++a)
    add_contact(sums, problem, r, u, a, terms);
  return natural_map_error(sums, q_is_zero(problem, q_zero_tolerance));
}
} // namespace
//-----------------------------------------------------------------------------
bool softpack::contact::is_q_zero(const FrictionContactProblem2D& problem,
                                  double q_zero_tolerance)
{
  return q_is_zero(problem, q_zero_tolerance);
}
//-----------------------------------------------------------------------------
bool softpack::contact::is_q_zero(const FrictionContactProblem3D& problem,
                                  double q_zero_tolerance)
{
  return q_is_zero(problem, q_zero_tolerance);
}
//-----------------------------------------------------------------------------
ErrorSums softpack::contact::error_sums(const FrictionContactProblem2D& problem,
                                        std::span<const double> r,
                                        std::span<double> u,
                                        std::span<const std::int32_t> rows)
{
  return sums_over(problem, r, u, rows);
}
//-----------------------------------------------------------------------------
ErrorSums softpack::contact::error_sums(const FrictionContactProblem3D& problem,
                                        std::span<const double> r,
                                        std::span<double> u,
                                        std::span<const std::int32_t> rows)
{
  return sums_over(problem, r, u, rows);
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
  return full_error(problem, r, u, q_zero_tolerance);
}
//-----------------------------------------------------------------------------
NaturalMapError
softpack::contact::compute_error(const FrictionContactProblem3D& problem,
                                 std::span<const double> r, std::span<double> u,
                                 double q_zero_tolerance)
{
  return full_error(problem, r, u, q_zero_tolerance);
}
//-----------------------------------------------------------------------------
