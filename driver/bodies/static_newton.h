#pragma once

#include "BodySet.h"
#include <span>
#include <vector>

namespace softpack::bodies
{

/// Options of the static Newton solver.
struct NewtonOptions
{
  /// Stop when ||r|| <= relative_tolerance * ||r_0||
  double relative_tolerance = 1e-10;
  /// ... or when ||r|| <= absolute_tolerance
  double absolute_tolerance = 1e-14;
  /// Give up after this many iterations
  int max_iterations = 30;
};

/// What the Newton solver did.
struct NewtonHistory
{
  /// Euclidean norm of the free-DOF residual, before each iteration and at
  /// the end
  std::vector<double> residual_norms;
  /// Whether a tolerance was met
  bool converged = false;
};

/// Solve the static equilibrium \f$F_{int}(u) = f_{ext}\f$ of all bodies by
/// Newton's method, with some DOFs prescribed (Dirichlet).
///
/// Each Newton step solves the block-diagonal system body by body (sparse
/// LDL^T per body). The prescribed values are imposed on the current
/// displacement before the first iteration.
/// @param[in,out] bodies Bodies; their displacement is the initial guess and
/// receives the solution
/// @param[in] f_ext External nodal forces (global DOF vector)
/// @param[in] fixed_dofs Global scalar DOF indices that are prescribed
/// @param[in] fixed_values Their displacement values
/// @param[in] options Tolerances
NewtonHistory solve_static_equilibrium(BodySet& bodies,
                                       std::span<const double> f_ext,
                                       std::span<const std::int32_t> fixed_dofs,
                                       std::span<const double> fixed_values,
                                       const NewtonOptions& options = {});

} // namespace softpack::bodies
