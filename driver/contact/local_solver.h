#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace softpack::contact
{

/// Which branch of the 2D Signorini–Coulomb law a contact is on. With a
/// cohesion c the conditions hold for the shifted reaction
/// \f$r' = r + c e_n\f$: `separated` is then the open cohesive contact,
/// \f$r = (-c, 0)\f$, `stick` the adhesive stick (a tensile \f$r_n\f$
/// possible) and the slides have \f$|r_t| = \mu (r_n + c)\f$.
enum class ContactStatus : std::uint8_t
{
  separated,      ///< \f$r = 0\f$, \f$u_n \ge 0\f$
  stick,          ///< \f$u = 0\f$, \f$|r_t| \le \mu r_n\f$
  slide_positive, ///< \f$u_n = 0\f$, \f$u_t \ge 0\f$, \f$r_t = -\mu r_n\f$
  slide_negative, ///< \f$u_n = 0\f$, \f$u_t \le 0\f$, \f$r_t = +\mu r_n\f$
  closest         ///< no branch held in floating point; least residual taken
};

/// Solution of one contact's local problem.
struct LocalSolution
{
  Eigen::Vector2d r = Eigen::Vector2d::Zero(); ///< reaction (n, t)
  ContactStatus status = ContactStatus::separated;
};

/// Solve the 2x2 local problem of one contact exactly: find \f$r\f$ with
/// \f$u = W r + q\f$,
/// \f$0 \le u_n \perp r_n \ge 0\f$, \f$|r_t| \le \mu r_n\f$ and
/// \f$r_t = -\mu r_n \operatorname{sign}(u_t)\f$ when \f$u_t \ne 0\f$.
///
/// The branches are tried in the order separation (\f$q_n \ge 0\f$), stick
/// (\f$r = -W^{-1} q\f$ inside the cone), slide with \f$u_t \ge 0\f$
/// (\f$r_n = -q_n / (W_{nn} - \mu W_{nt})\f$) and slide with \f$u_t \le 0\f$
/// (\f$r_n = -q_n / (W_{nn} + \mu W_{nt})\f$); the first whose conditions
/// hold is returned. When none holds because of rounding at a branch
/// boundary, the candidate with the smallest natural-map residual is
/// returned with status ContactStatus::closest.
///
/// @param[in] W Diagonal Delassus block \f$W_{aa}\f$, \f$W_{nn} > 0\f$
/// @param[in] q Local free velocity, including the coupling
///   \f$\sum_{b \ne a} W_{ab} r_b\f$ with the other contacts
/// @param[in] mu Coulomb coefficient, \f$\mu \ge 0\f$
/// @return The reaction and its branch
LocalSolution solve_local(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                          double mu);

/// Solve the 2x2 local problem of a cohesive contact exactly: the law of
/// solve_local(W, q, mu) in the shifted reaction \f$r' = r + c e_n\f$,
/// \f$0 \le u_n \perp r_n + c \ge 0\f$, \f$|r_t| \le \mu (r_n + c)\f$.
/// Since \f$u = W r' + (q - c W e_n)\f$, it is solve_local() with the
/// free velocity \f$q' = q - c W e_n\f$, its reaction shifted back.
/// With c = 0 it is solve_local(W, q, mu) itself (the same operations).
/// @param[in] c Cohesion, an impulse, \f$c \ge 0\f$
LocalSolution solve_local(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                          double mu, double c);

} // namespace softpack::contact
