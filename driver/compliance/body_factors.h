#pragma once

#include "general_factor.h"
#include <Eigen/SparseCholesky>
#include <bodies/BodySet.h>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// The sparse LDL^T factors of one symmetric positive definite matrix per
/// body, kept compactly:
/// - bodies whose matrices have one sparsity pattern once their nodes are
///   put in input order (Body::input_position: copies of one template mesh)
///   share one symbolic factorization (fill-reducing AMD ordering of the
///   nodes and the pattern of L by 2x2 node blocks), computed once;
/// - each body keeps only its own values of L, in single precision, D and
///   its permutation. The products are formed in double precision.
///
/// Single precision is enough because the factors drive a modified Newton
/// iteration, whose matrix is already up to 50 steps old: their 6e-8
/// relative rounding changes the iteration's contraction, not the
/// residual it converges on (the Delassus blocks come from the same
/// solves, so the contact problem stays consistent with the update).
/// Against double values with per-body indices (Eigen::SimplicialLDLT kept
/// per body) this takes a third of the memory (4 bytes per entry of L
/// instead of 12), and the solves, which stream L from memory, read a
/// third of the bytes (measured: solves 7 % faster on the paper case, 18 %
/// at 1,000 disks; docs/performance.md). L kept by 2x2 node blocks has the
/// same entries as the scalar L under the nodes' ordering (AMD keeps a
/// node's DOFs together anyway), one index per block instead of one per
/// entry: the paper case's solves ran 21 % faster (its factors sit in
/// cache), those of 1,000 disks no faster (they stream from memory).
///
/// 3D bodies (BodySet::dim() = 3) keep one GeneralFactor per body, in
/// double precision (the compact 2x2-block storage is the plane-strain
/// bodies' so far): by default CHOLMOD's supernodal Cholesky, analyzed once
/// per body (its pattern never changes: the fill-reducing ordering and the
/// supernodes are computed in the constructor) and factorized numerically
/// at each refactorization; its solves take several right-hand sides at
/// once (a boundary node's compliance columns,
/// EffectiveStiffness::prepare_columns), through BLAS 3. Against Eigen's
/// SimplicialLDLT redoing its AMD analysis at each refactorization and
/// solving one column at a time, a nodal-pressure cylinder's
/// factorizations and Delassus columns run about ten times faster
/// (docs/performance_3d.md, "Factors of 3D bodies").
class BodyFactors
{
public:
  /// @param[in] bodies The bodies (their input_position and node counts);
  /// their local bodies are factorized (BodySet::local_bodies)
  /// @param[in] patterns One lower-triangular matrix per body giving its
  /// sparsity pattern, with values of a positive definite matrix on it
  /// (the consistent masses): the symbolic factorizations are taken from
  /// them
  BodyFactors(const bodies::BodySet& bodies,
              const std::vector<bodies::BodyMatrix>& patterns);

  /// Fills `matrix` (a copy of body b's pattern) with body b's values.
  using Former = std::function<void(int b, bodies::BodyMatrix& matrix)>;

  /// Factorize every owned body's matrix, as `form` gives it (called in
  /// parallel, one body per call).
  /// @return false if a matrix is not positive definite
  bool factorize(const Former& form);

  /// Solve \f$A_b x = y\f$ for body b (local DOF numbering).
  Eigen::VectorXd solve(int b, const Eigen::VectorXd& y) const;

  /// Solve \f$A_b X = Y\f$ for body b, many right-hand sides at once
  /// (3D bodies only: the 2D factors solve one column at a time).
  /// @throws std::logic_error for 2D bodies
  Eigen::MatrixXd solve(int b, const Eigen::MatrixXd& Y) const;

  /// Whether solve(b, Y) with many columns is available (3D bodies)
  bool solves_blocks() const { return _dim != 2; }

  /// Number of DOFs of body b
  int rows(int b) const { return _rows[b]; }

  /// Number of distinct symbolic factorizations
  int num_patterns() const { return static_cast<int>(_symbolic.size()); }

  /// Entries of L kept by body b (its single-precision values)
  std::size_t factor_entries(int b) const { return _values[b].size(); }

private:
  /// What the bodies of one pattern share, in the fill-reducing order
  /// (which keeps a node's two DOFs together, x first): L by 2x2 blocks of
  /// nodes, each node column's block rows (below its diagonal block), and
  /// where each entry of the scalar factor goes among a body's values
  struct Symbolic
  {
    std::vector<int> block_start, block_row;
    /// Per entry of Eigen's scalar L (in its order): its index in a body's
    /// values (4 per block, column by column, then one per node: the
    /// entry of its y row in its x column)
    std::vector<int> destination;
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> ordering;
    int num_nodes() const { return static_cast<int>(block_start.size()) - 1; }
  };
  void analyze(Symbolic& s, const bodies::BodyMatrix& canonical);
  /// factorize() and solve() of the 3D bodies
  bool factorize_general(const Former& form);

  /// Components per node (BodySet::dim)
  int _dim = 2;
  /// 3D: each local body's factor, analyzed (empty in 2D)
  std::vector<std::unique_ptr<GeneralFactor>> _general;

  const std::vector<bodies::BodyMatrix>* _patterns;
  std::vector<Symbolic> _symbolic;
  /// Per body: its DOFs, its pattern, the permutation from its local DOFs
  /// to the factor's order (owned bodies only), L's values
  /// (Symbolic::destination), D's inverse
  std::vector<int> _rows, _pattern_of;
  std::vector<Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>>
      _perm;
  std::vector<std::vector<float>> _values;
  std::vector<Eigen::VectorXd> _inverse_d;
};

} // namespace softpack::dynamics
