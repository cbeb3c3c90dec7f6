#pragma once

#include "problem.h"

#include <Eigen/Core>
#include <span>

namespace softpack::contact
{

/// Euclidean projection onto the 2D Coulomb cone
/// \f$K_\mu = \{ (r_n, r_t) : |r_t| \le \mu r_n \}\f$.
/// @param[in] x Point (n, t)
/// @param[in] mu Coulomb coefficient, \f$\mu \ge 0\f$
/// @return \f$\mathrm{proj}_{K_\mu}(x)\f$
Eigen::Vector2d project_on_cone(const Eigen::Vector2d& x, double mu);

/// Euclidean projection onto the 3D (circular) Coulomb cone
/// \f$K_\mu = \{ (r_n, r_t) : |r_t| \le \mu r_n \}\f$, \f$r_t \in
/// \mathbb{R}^2\f$: the 2D formula with \f$|x_t|\f$ the length of the
/// tangential part, the projection staying in the plane of \f$e_n\f$ and
/// \f$x_t\f$.
/// @param[in] x Point (n, t1, t2)
/// @param[in] mu Coulomb coefficient, \f$\mu \ge 0\f$
/// @return \f$\mathrm{proj}_{K_\mu}(x)\f$
/// (A template of the 3-vector only, so that a braced pair {x_n, x_t}
/// still names the 2D cone.)
template <int D>
requires(D == 3) Eigen::Matrix<double, D, 1> project_on_cone(
    const Eigen::Matrix<double, D, 1>& x, double mu);

/// Squared natural-map residual of one contact with the De Saxcé velocity:
/// \f[
///   \| r - \mathrm{proj}_{K_\mu}(r - \tilde u) \|^2, \qquad
///   \tilde u = (u_n + \mu |u_t|, \; u_t).
/// \f]
/// It is zero exactly when (r, u) satisfy Signorini and Coulomb.
/// @param[in] r Reaction (n, t)
/// @param[in] u Velocity (n, t)
/// @param[in] mu Coulomb coefficient
/// @return The squared residual
double natural_map_residual_squared(const Eigen::Vector2d& r,
                                    const Eigen::Vector2d& u, double mu);

/// The same in 3D, \f$\tilde u = (u_n + \mu |u_t|, u_t)\f$ with
/// \f$|u_t|\f$ the length of the tangential velocity (Siconos
/// `fc3d_compute_error`'s per-contact term)
template <int D>
requires(D == 3) double natural_map_residual_squared(
    const Eigen::Matrix<double, D, 1>& r, const Eigen::Matrix<double, D, 1>& u,
    double mu);

/// The reaction of a cohesive contact in the variable of its cone,
/// \f$r' = r + c e_n\f$ (r itself when c = 0)
/// @param[in] r Reaction (n, t) or (n, t1, t2)
/// @param[in] c Cohesion, an impulse
template <int D>
inline Eigen::Matrix<double, D, 1>
shifted_reaction(Eigen::Matrix<double, D, 1> r, double c)
{
  if (c != 0)
    r[0] += c;
  return r;
}

/// The error of a candidate solution (Siconos `fc2d_compute_error`,
/// `fc3d_compute_error`).
struct NaturalMapError
{
  /// \f$\big(\sum_a \|r_a - \mathrm{proj}_K(r_a - \tilde u_a)\|^2\big)^{1/2}\f$
  double absolute = 0;

  /// \f$\max(\|r\|, \|u\|, \|q\|)\f$
  double scale = 0;

  /// true when q = 0 within the given tolerance: the answer is r = 0 and a
  /// relative error would only measure rounding noise in q
  bool q_zero = false;

  /// The error compared with a tolerance: absolute/scale (Siconos: not
  /// divided when scale <= machine epsilon), or absolute when q_zero
  double value = 0;
};

/// True when \f$\|q\|_\infty \le\f$ q_zero_tolerance: the problem is
/// trivial, with the solution r = 0, u = q.
/// @param[in] problem The problem
/// @param[in] q_zero_tolerance Absolute threshold (velocity units)
bool is_q_zero(const FrictionContactProblem2D& problem,
               double q_zero_tolerance);
bool is_q_zero(const FrictionContactProblem3D& problem,
               double q_zero_tolerance);

/// The sums behind a NaturalMapError, over some of the contacts (a domain's
/// share of a distributed problem: the shares add up)
struct ErrorSums
{
  /// of the squared natural-map residuals, of |r_a|^2, |u_a|^2, |q_a|^2
  double residual = 0, r = 0, u = 0, q = 0;
};

/// ErrorSums over the contacts `rows`, their u = W r + q computed here
/// from their rows of W (the reactions these rows read must be current).
/// @param[out] u Written at `rows` only
ErrorSums error_sums(const FrictionContactProblem2D& problem,
                     std::span<const double> r, std::span<double> u,
                     std::span<const std::int32_t> rows);
ErrorSums error_sums(const FrictionContactProblem3D& problem,
                     std::span<const double> r, std::span<double> u,
                     std::span<const std::int32_t> rows);

/// The error from the sums over every contact
/// @param[in] q_zero is_q_zero() of the problem
NaturalMapError natural_map_error(const ErrorSums& sums, bool q_zero);

/// Full error of (r, u = W r + q), u recomputed here (one pass over W).
/// A cohesive contact's residual is that of its shifted reaction
/// (shifted_reaction()); its norm in the scale is that of r itself.
/// \f[
///   e = \frac{\big(\sum_a \|r_a - \mathrm{proj}_{K_{\mu_a}}(r_a - \tilde
///   u_a)\|^2\big)^{1/2}}{\max(\|r\|, \|u\|, \|q\|)}
/// \f]
/// @param[in] problem The problem
/// @param[in] r Reactions, D per contact
/// @param[out] u Velocities W r + q, D per contact
/// @param[in] q_zero_tolerance See is_q_zero(); then the error is absolute
/// @return The error terms
NaturalMapError compute_error(const FrictionContactProblem2D& problem,
                              std::span<const double> r, std::span<double> u,
                              double q_zero_tolerance);
NaturalMapError compute_error(const FrictionContactProblem3D& problem,
                              std::span<const double> r, std::span<double> u,
                              double q_zero_tolerance);

} // namespace softpack::contact
