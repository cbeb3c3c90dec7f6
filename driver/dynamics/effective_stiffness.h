#pragma once

#include <Eigen/SparseCholesky>
#include <bodies/BodySet.h>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// The iteration matrix of the Moreau–Jean scheme, one block per body:
/// \f[
///   \bar K = M + h\theta C + h^2\theta^2 K
///          = (1 + h\theta\alpha) M + (h\theta\beta + h^2\theta^2) K,
/// \f]
/// with Rayleigh damping \f$C = \alpha M + \beta K\f$. Each body's block is
/// factorized on its own (sparse LDL^T; the symbolic analysis is done once
/// and reused), so solves, refactorizations and compliance computations
/// stay per body.
class EffectiveStiffness
{
public:
  /// @param[in] bodies Bodies (masses and sparsity patterns)
  /// @param[in] lumped_mass Use the lumped (diagonal) mass instead of the
  /// consistent one
  /// @param[in] owned The bodies this rank factorizes (1; empty: all): a
  /// distributed run's other bodies keep their masses only
  EffectiveStiffness(const bodies::BodySet& bodies, bool lumped_mass,
                     std::span<const char> owned = {});

  /// Build and factorize \f$\bar K = a M + c K\f$ for every body.
  /// @param[in] K Tangent stiffness of every body (BodySet::tangent)
  /// @param[in] mass_coefficient a
  /// @param[in] stiffness_coefficient c
  /// @throws std::runtime_error if a block is not positive definite
  void factorize(const std::vector<bodies::BodyMatrix>& K,
                 double mass_coefficient, double stiffness_coefficient);

  /// Solve \f$\bar K_b x = y\f$ for body b (local DOF numbering).
  Eigen::VectorXd solve(int body, const Eigen::VectorXd& y) const
  {
    return _factors[body].solve(y);
  }

  /// Compliance \f$\bar K_b^{-1}\f$ of body b restricted to its boundary
  /// DOFs (2 per boundary node, in the order of Body::boundary_nodes). Only
  /// the columns of the given boundary slots are guaranteed: they are
  /// computed on first demand after each factorization (one solve per DOF)
  /// and kept until the next one, so the cost follows the nodes that
  /// actually carry contacts.
  const Eigen::MatrixXd& boundary_compliance(int body,
                                             std::span<const int> slots) const;

  /// \f$(\bar K_b^{-1} y)\f$ at the two DOFs of a boundary slot, from the
  /// kept compliance columns (\f$\bar K\f$ is symmetric: a row of the
  /// inverse is a column): two dot products instead of a solve.
  /// @pre boundary_compliance() was called with this slot since the last
  /// factorization
  Eigen::Vector2d boundary_response(int body, int slot,
                                    const Eigen::VectorXd& y) const
  {
    const std::vector<Eigen::VectorXd>& C = _columns[body];
    return {C[2 * slot].dot(y), C[2 * slot + 1].dot(y)};
  }

  /// Position of a local node in Body::boundary_nodes (-1 if interior)
  int boundary_slot(int body, std::int32_t node) const
  {
    return _slot[body][node];
  }

  /// Mass matrix of body b, on the body's stiffness pattern
  const bodies::BodyMatrix& mass(int body) const { return _mass[body]; }

  /// Number of factorizations done so far (all bodies count as one)
  int factorizations() const { return _count; }

private:
  std::vector<bodies::BodyMatrix> _mass, _kbar;
  std::vector<Eigen::SimplicialLDLT<bodies::BodyMatrix>> _factors;
  std::vector<std::vector<std::int32_t>> _boundary, _slot;
  /// Boundary rows (G) of each body's compliance at its boundary DOFs ...
  mutable std::vector<Eigen::MatrixXd> _compliance;
  /// ... and its whole columns (C), allocated only for the boundary DOFs
  /// that carried a contact since the last factorization (empty vectors
  /// otherwise): they are most of the driver's memory, and only the
  /// contact nodes' columns are ever needed
  mutable std::vector<std::vector<Eigen::VectorXd>> _columns;
  mutable std::vector<std::vector<char>> _column_ready;
  int _count = 0;
  std::vector<char> _owned;
};

} // namespace softpack::dynamics
