#pragma once

#include <Eigen/Core>
#include <bodies/BodySet.h>

namespace softpack::dynamics
{

/// Rayleigh damping \f$C = \alpha M + \beta K\f$ (paper Eq. 10), with K
/// the current tangent stiffness: the one place where C is written. The
/// iteration matrix, the known part of the momentum balance and the energy
/// accounts all take C from here.
struct RayleighDamping
{
  /// Mass coefficient alpha (1/s)
  double alpha = 0;
  /// Stiffness coefficient beta (s)
  double beta = 0;

  /// The damping force \f$C v = \alpha (M v) + \beta (K v)\f$ of a body.
  /// @param[in] Mv The body's M v
  /// @param[in] Kv The body's K v
  Eigen::VectorXd force(const Eigen::VectorXd& Mv,
                        const Eigen::VectorXd& Kv) const
  {
    return alpha * Mv + beta * Kv;
  }

  /// Coefficients (a, c) of a combination a M + c K
  struct Combination
  {
    double mass, stiffness;
  };

  /// \f$M + s C = (1 + s\alpha) M + s\beta K\f$
  Combination mass_plus(double s) const { return {1 + s * alpha, s * beta}; }
};

/// out = a M + c K, value by value: M, K and out share one sparsity pattern
/// (the body's stiffness pattern).
/// @param[in] combination (a, c)
/// @param[in] M Mass matrix of a body
/// @param[in] K Stiffness matrix of the body
/// @param[in,out] out A matrix on the same pattern; its values are replaced
void combine(RayleighDamping::Combination combination,
             const bodies::BodyMatrix& M, const bodies::BodyMatrix& K,
             bodies::BodyMatrix& out);

/// (a M + c K) v without forming a M + c K: one pass over the shared
/// pattern (the lower triangle of symmetric matrices, BodyMatrix), so that
/// no third matrix per body is stored.
/// @param[in] combination (a, c)
/// @param[in] M Mass matrix of a body
/// @param[in] K Stiffness matrix of the body, on M's pattern
/// @param[in] v A vector of the body's DOFs
Eigen::VectorXd combined_product(RayleighDamping::Combination combination,
                                 const bodies::BodyMatrix& M,
                                 const bodies::BodyMatrix& K,
                                 const Eigen::VectorXd& v);

} // namespace softpack::dynamics
