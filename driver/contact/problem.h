#pragma once

#include "DelassusMatrix.h"

#include <cstddef>
#include <vector>

namespace softpack::contact
{

/// A frictional contact problem in local (Delassus) form in D = 2 or 3
/// dimensions, as in Siconos and FCLIB: find reactions \f$r\f$ and
/// velocities \f$u\f$ with
/// \f[
///   u = W r + q, \qquad
///   0 \le u_{n,a} \perp r_{n,a} \ge 0, \qquad
///   |r_{t,a}| \le \mu_a r_{n,a}, \qquad
///   r_{t,a} = -\mu_a r_{n,a} \operatorname{sign}(u_{t,a})
///   \text{ if } u_{t,a} \ne 0,
/// \f]
/// for every contact \f$a\f$, each vector holding (n, t) per contact in 2D,
/// (n, t1, t2) in 3D, where \f$r_t, u_t \in \mathbb{R}^2\f$, the cone is
/// circular and the sign is \f$u_t / |u_t|\f$
/// (FrictionContactProblem2D, FrictionContactProblem3D).
///
/// A contact with a cohesion \f$c_a > 0\f$ (an impulse: docs/contact_laws.md)
/// obeys the same law in the shifted reaction \f$r'_a = r_a + c_a e_n\f$:
/// \f$0 \le u_{n,a} \perp r_{n,a} + c_a \ge 0\f$,
/// \f$|r_{t,a}| \le \mu_a (r_{n,a} + c_a)\f$, sliding as above; so its
/// normal reaction may be tensile down to \f$-c_a\f$, which it is whenever
/// the contact opens (\f$u_{n,a} > 0\f$).
/// Plain data: the algorithms take it by const reference.
template <int D> struct FrictionContactProblem
{
  /// Number of unknowns per contact
  static constexpr int dimension = D;

  /// Delassus operator, finalized
  DelassusMatrixD<D> W;

  /// Free velocity, D per contact in (n, t...) order
  std::vector<double> q;

  /// Coulomb friction coefficient \f$\mu_a\f$, one per contact (FCLIB
  /// files call it vectors/mu)
  std::vector<double> friction;

  /// Cohesion \f$c_a \ge 0\f$ of each contact, an impulse (force times
  /// the time step); empty: 0 for every contact (the plain
  /// Signorini–Coulomb problem, solved by the very same operations)
  std::vector<double> cohesion;

  /// @return The cohesion of contact a (0 when none is given)
  double cohesion_of(std::size_t a) const
  {
    return cohesion.empty() ? 0.0 : cohesion[a];
  }

  /// @return Number of contacts
  std::size_t num_contacts() const { return friction.size(); }
};

using FrictionContactProblem2D = FrictionContactProblem<2>;
using FrictionContactProblem3D = FrictionContactProblem<3>;

/// Check that a problem is well formed: W finalized with one block row per
/// contact, sizes of q, friction and cohesion (empty or one per contact),
/// finite values, \f$\mu \ge 0\f$, \f$c \ge 0\f$ and a
/// positive normal compliance \f$(W_{aa})_{nn} > 0\f$ on every diagonal block.
/// @param[in] problem The problem
/// @throws std::invalid_argument naming the first violation found
void validate(const FrictionContactProblem2D& problem);
void validate(const FrictionContactProblem3D& problem);

} // namespace softpack::contact
