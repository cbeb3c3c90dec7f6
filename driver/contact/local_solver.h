#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace softpack::contact
{

/// Which branch of the Signorini–Coulomb law a contact is on (2D: the
/// slides by the sign of \f$u_t\f$; 3D: `slide`, in any direction). With a
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
  closest,        ///< no branch held in floating point; least residual taken
  slide           ///< 3D: \f$u_n = 0\f$, \f$r_t = -\mu r_n u_t / |u_t|\f$
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

/// Solution of one contact's 3D local problem.
struct LocalSolution3D
{
  Eigen::Vector3d r = Eigen::Vector3d::Zero(); ///< reaction (n, t1, t2)
  ContactStatus status = ContactStatus::separated;
};

/// Solve the 3x3 local problem of one contact exactly
/// (local_solver_3d.cpp): find \f$r\f$ with \f$u = W r + q\f$,
/// \f$0 \le u_n \perp r_n \ge 0\f$, \f$|r_t| \le \mu r_n\f$ and
/// \f$r_t = -\mu r_n u_t / |u_t|\f$ when \f$u_t \ne 0\f$ (circular cone,
/// \f$r_t, u_t \in \mathbb{R}^2\f$).
///
/// The branches, in order: separation (\f$q_n \ge 0\f$: r = 0); with
/// \f$\mu = 0\f$ the frictionless reaction \f$r = (-q_n / W_{nn}, 0, 0)\f$;
/// stick (\f$r = -W^{-1} q\f$ inside the cone); slide in the direction
/// \f$s = (\cos\theta, \sin\theta)\f$: \f$r = r_n (1, -\mu s)\f$ with
/// \f$u_n = 0\f$ gives \f$r_n(\theta) = -q_n / (W_{nn} - \mu W_{nt} s)\f$, and
/// \f$u_t(\theta) \parallel s\f$ is, times that denominator,
/// \f$g(\theta) = s^\perp \cdot (h_0 + H_1 s) = 0\f$ with
/// \f$h_0 = W_{nn} q_t - q_n W_{tn}\f$,
/// \f$H_1 = \mu (q_n W_{tt} - q_t W_{nt})\f$: a trigonometric polynomial
/// of degree 2, whose (at most 4) roots are those on the unit circle of a
/// quartic in \f$z = e^{i\theta}\f$ (the eigenvalues of its companion
/// matrix, each polished by Newton on \f$g\f$). A root is a slide when
/// \f$r_n \ge 0\f$ and \f$s \cdot u_t \ge 0\f$; of several (a large
/// \mu can allow more than one) the least natural-map residual is taken.
/// When no branch holds in floating point the candidate of least residual,
/// projected on the cone, is returned with ContactStatus::closest.
///
/// @param[in] W Diagonal Delassus block \f$W_{aa}\f$, \f$W_{nn} > 0\f$ (need
///   not be symmetric)
/// @param[in] q Local free velocity with the other contacts' coupling
/// @param[in] mu Coulomb coefficient, \f$\mu \ge 0\f$
/// @return The reaction and its branch (separated, stick, slide, closest)
LocalSolution3D solve_local(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                            double mu);

/// The 3D cohesive local problem: solve_local(W, q - c W e_n, mu), its
/// reaction shifted back by \f$-c e_n\f$ (as in 2D); c = 0 is
/// solve_local(W, q, mu) itself.
LocalSolution3D solve_local(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                            double mu, double c);

} // namespace softpack::contact
