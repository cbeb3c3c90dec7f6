#pragma once
// The algebra of one held set of frictionless contacts
// (FrictionlessCondensation): W_SS factored, the correction it makes to the
// reduced W, and the reduced W's diagonal blocks made definite.
#include "DelassusMatrix.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace softpack::contact
{

/// One set's held contacts S condensed: r_S = -(y + X r_P) at the kept
/// contacts P that W couples to them (`neighbours`); the reduced problem
/// has W_PP - C X and q_P - C y
struct HeldSet
{
  std::vector<std::int32_t> held, neighbours;
  /// X = W_SS^-1 W_SP (m x D p), C = W_PS (D p x m), y = W_SS^-1 q_S (of
  /// the solve's q)
  Eigen::MatrixXd X, C;
  Eigen::VectorXd y;
  /// W_SS = P^T L D L^T P (its normal blocks made symmetric: W is, to its
  /// blocks' rounding)
  Eigen::LDLT<Eigen::MatrixXd> ldlt;

  /// Factor W_SS = N (m x m) and make X from W_SP = B
  /// @throws std::runtime_error if N is not positive definite
  void factor(const Eigen::MatrixXd& N, const Eigen::MatrixXd& B);

  /// Whether the reduced W takes C X as its m rank-one terms rather than
  /// as p^2 blocks: a sweep then reads 2 m terms at each neighbour instead
  /// of p blocks (the dense 100 cylinders: m ~ 4 pushing base nodes a
  /// body, p ~ 200 neighbours; a body settling on the base: m > p)
  bool as_terms() const { return held.size() < neighbours.size(); }

  /// Subtract C X from the reduced W: its off-diagonal part as blocks or
  /// as rank-one terms (as_terms()), its diagonal blocks' share from
  /// `diagonal`. `place`: each contact's number in the reduced problem.
  template <int D>
  void subtract_correction(
      std::span<const std::int32_t> place, DelassusMatrixD<D>& reduced_W,
      std::vector<typename DelassusMatrixD<D>::Block>& diagonal) const;
};

/// A diagonal block of the reduced W, made definite: a contact that moves
/// its node along a held contact's normal (the rim node's neighbour, its
/// friction along the base's normal) keeps no compliance that way, and
/// the Schur complement leaves a zero eigenvalue of either sign at
/// rounding (1e-16 of the block), on which the local solver's sticking
/// answer is not finite. Eigenvalues below 1e-10 of the block's trace are
/// raised to it: the velocities move by at most that fraction of the
/// block's own, far below any contact tolerance; blocks without one are
/// returned as they are.
template <int D>
Eigen::Matrix<double, D, D> definite(const Eigen::Matrix<double, D, D>& block);

} // namespace softpack::contact
