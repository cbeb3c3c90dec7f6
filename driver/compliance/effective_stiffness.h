#pragma once

#include "body_factors.h"
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
/// factorized on its own (BodyFactors: in 2D a sparse LDL^T with one
/// symbolic analysis per distinct mesh, in 3D CHOLMOD's supernodal
/// Cholesky analyzed once per body), so solves, refactorizations and
/// compliance computations stay per body.
class EffectiveStiffness
{
public:
  /// @param[in] bodies Bodies (masses and sparsity patterns); must outlive
  /// this object (the consistent masses are read from it, not copied)
  /// @param[in] lumped_mass Use the lumped (diagonal) mass instead of the
  /// consistent one
  /// The bodies' local ones are factorized (BodySet::local_bodies); the
  /// others keep their masses only
  EffectiveStiffness(const bodies::BodySet& bodies, bool lumped_mass);

  /// Factorize the bodies' new local ones from now on (after
  /// BodySet::set_local, a rebalanced run): their symbolic analyses are
  /// done again and every compliance column is dropped; the next
  /// factorize() makes the factors.
  void set_local(const bodies::BodySet& bodies);

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
    return _factors.solve(body, y);
  }

  /// Make the compliance columns \f$\bar K_b^{-1} e\f$ of the given
  /// boundary slots of body b available (dim per slot; one solve each in
  /// 2D; in 3D one solve for all the columns of a slot's group,
  /// column_groups): they are computed on first demand after each
  /// factorization and kept until
  /// the next one, so the cost follows the nodes that actually carry
  /// contacts. Only their rows at the body's boundary nodes are kept: the
  /// Delassus blocks read nothing else.
  void prepare_columns(int body, std::span<const int> slots) const;

  /// The D x D block of \f$\bar K_b^{-1}\f$ between boundary slots i
  /// (rows) and j (columns), read off the kept columns (D the bodies'
  /// dimension).
  /// @pre prepare_columns() was called with slot j since the last
  /// factorization
  template <int D = 2>
  Eigen::Matrix<double, D, D> boundary_block(int body, int i, int j) const
  {
    const std::vector<Column>& C = _columns[body];
    Eigen::Matrix<double, D, D> block;
    for (int c = 0; c < D; ++c)
      for (int r = 0; r < D; ++r)
        block(r, c) = C[D * j + c][D * i + r];
    return block;
  }

  /// The boundary slots of body b in groups of at most 8
  /// that lie close together (consecutive along a Z-order curve of their
  /// reference positions), made on the first demand (3D bodies): a 3D body's
  /// compliance columns are solved a whole group at a time. Contacts load
  /// patches of nodes, so a group's columns are mostly needed together
  const std::vector<std::vector<std::int32_t>>& column_groups(int b) const;

  /// Position of a local node in Body::boundary_nodes (-1 if interior)
  int boundary_slot(int body, std::int32_t node) const
  {
    return _slot[body][node];
  }

  /// Mass matrix of body b, on the body's stiffness pattern (empty for a
  /// body whose mass the body set does not keep: BodySet::kept_masses)
  const bodies::BodyMatrix& mass(int body) const { return (*_mass)[body]; }

  /// Number of factorizations done so far (all bodies count as one)
  int factorizations() const { return _count; }

  /// Distinct symbolic factorizations (BodyFactors::num_patterns)
  int factor_patterns() const { return _factors.num_patterns(); }

private:
  /// A compliance column's rows at the body's boundary nodes (dim per slot),
  /// in double precision: the Delassus blocks built from them must be
  /// those of the solves that update the velocity (H Kbar^-1 H^T to the
  /// last digit), or the Newton iteration of a closed contact stalls at
  /// their difference (float columns with float factors: a two-cycle at
  /// 1e-8 m/s in tests/cpp/dynamics/test_plates.cpp). Whole columns were
  /// the largest item of a crowded run's memory; their boundary rows are
  /// a tenth of it.
  using Column = Eigen::VectorXd;
  /// prepare_columns() of 3D bodies: the columns of a new slot's whole
  /// group (column_groups), d per slot, by one solve of their right-hand
  /// sides. Always the same ones together, so that a column does not
  /// depend on which other slots are new: BLAS rounds a column differently
  /// with the block's make-up, and a resumed run's columns (all of them new
  /// at once) must be the uninterrupted run's to the last bit
  /// (tests/python/test_mpi_3d.py). One solve of a group's many columns
  /// reads the factor once (BLAS 3) where one per slot read it for three.
  void prepare_column_blocks(int body, std::span<const int> slots) const;
  /// Put the lumped masses of the kept bodies on the stiffness pattern
  void build_lumped(const bodies::BodySet& bodies);
  /// The masses on the stiffness pattern: the bodies' consistent masses
  /// (BodySet keeps them on that pattern), or _lumped, the lumped masses
  /// put on it. Kbar itself is not kept: each factorization forms it in a
  /// scratch matrix (a per-body copy was a fifth of the driver's memory).
  const std::vector<bodies::BodyMatrix>* _mass;
  std::vector<bodies::BodyMatrix> _lumped;
  BodyFactors _factors;
  std::vector<std::vector<std::int32_t>> _boundary, _slot;
  /// The compliance columns of each body, allocated only for the boundary
  /// DOFs that carried a contact since the last factorization (empty
  /// vectors otherwise): only the contact nodes' columns are ever needed,
  /// and only their rows at other contact nodes (the Delassus blocks)
  mutable std::vector<std::vector<Column>> _columns;
  mutable std::vector<std::vector<char>> _column_ready;
  /// Per body: its slots' groups (column_groups) and each slot's group
  mutable std::vector<std::vector<std::vector<std::int32_t>>> _groups;
  mutable std::vector<std::vector<std::int32_t>> _group_of;
  /// The bodies' reference positions (BodySet::reference_coordinates)
  const bodies::BodySet* _bodies;
  int _count = 0;
  /// Components per node (BodySet::dim)
  int _dim = 2;
};

} // namespace softpack::dynamics
