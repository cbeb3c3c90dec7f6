#pragma once

#include "local_solver.h"
#include "problem.h"

#include <Eigen/Core>
#include <cstdint>
#include <span>

namespace softpack::contact
{

/// The strengths of an intact bond (docs/contact_laws.md, law "bonded"),
/// as impulses (force times the time step, per unit thickness: N s/m):
/// \f$T = \sigma_t s \ell h\f$ and \f$S = \tau_s s \ell h\f$.
struct BondStrength
{
  /// Tensile strength \f$T > 0\f$: the largest tensile normal reaction
  double tensile = 0;
  /// Shear strength \f$S > 0\f$: the largest tangential reaction without
  /// normal force
  double shear = 0;
};

/// A shifted Coulomb cone \f$|r_t| \le \mu (r_n + c)\f$: the arguments
/// \f$(\mu, c)\f$ of solve_local(W, q, mu, c) and the problem's
/// `friction` and `cohesion` entries of a contact.
struct ShiftedCone
{
  double coefficient = 0; ///< \f$\mu\f$
  double cohesion = 0;    ///< \f$c\f$, an impulse
};

/// The envelope of an intact bond as a shifted cone: the Mohr–Coulomb line
/// through \f$(-T, 0)\f$ and \f$(0, \pm S)\f$, i.e. \f$c = T\f$,
/// \f$\mu = S / T\f$. An intact bond is thus the cohesive law's contact
/// (solve_local() with a cohesion): bilateral in the normal direction down
/// to \f$-T\f$, stuck while \f$|r_t| < (S/T)(r_n + T)\f$.
/// @param[in] s The strengths, both > 0 and finite
/// @throws std::invalid_argument otherwise
ShiftedCone bond_cone(const BondStrength& s);

/// Solve the 2x2 local problem of an intact bond exactly:
/// solve_local(W, q, S/T, T) (bond_cone()).
/// @param[in] W Diagonal Delassus block, \f$W_{nn} > 0\f$
/// @param[in] q Local free velocity (the bond's gap shift and the coupling
///   to the other contacts included)
/// @param[in] s The bond's strengths
LocalSolution solve_bond(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                         const BondStrength& s);

/// Make some contacts of a problem intact bonds: their `friction` and
/// `cohesion` entries become those of bond_cone() (the cohesion vector is
/// made, 0 at the other contacts, if it was empty). With no contact listed
/// the problem is left untouched: the same problem, solved with the same
/// bits, as before bonds existed.
/// @param[in,out] problem The problem (friction sized, one per contact)
/// @param[in] contacts The bonded contacts
/// @param[in] strengths Their strengths, one per listed contact
/// @throws std::invalid_argument for sizes that differ, a contact out of
///   range or strengths bond_cone() refuses
void set_bonds(FrictionContactProblem2D& problem,
               std::span<const std::int32_t> contacts,
               std::span<const BondStrength> strengths);

/// What becomes of an intact bond after a step's contact solve.
enum class BondOutcome : std::uint8_t
{
  holds,   ///< reaction strictly inside the envelope: u = 0, stays intact
  tension, ///< \f$r_n + T \le \eta T\f$: pulled with its whole strength
  shear    ///< \f$|r_t| T \ge (1 - \eta) S (r_n + T)\f$: on the slope
};

/// The break rule of a bond (docs/contact_laws.md): a reaction on the
/// envelope of bond_cone(), within the relative tolerance eta of the
/// contact solve, breaks the bond (tension first, then shear).
/// @param[in] r The bond's reaction (n, t) at the end of the step
/// @param[in] s Its strengths (bond_cone()'s conditions)
/// @param[in] eta Relative tolerance, \f$0 \le \eta < 1\f$
BondOutcome bond_outcome(const Eigen::Vector2d& r, const BondStrength& s,
                         double eta);

} // namespace softpack::contact
