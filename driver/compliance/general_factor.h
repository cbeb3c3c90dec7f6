#pragma once

#include <Eigen/Core>
#include <bodies/BodySet.h>
#include <memory>
#include <string>

namespace softpack::dynamics
{

/// The factors of one 3D body's symmetric positive definite matrix, whose
/// sparsity pattern is fixed: analyzed once (fill-reducing ordering,
/// elimination tree, pattern of L), then factorized numerically again at
/// each refactorization. Two kinds:
/// - "cholmod" (the bodies'): CHOLMOD's supernodal Cholesky LL^T, whose
///   dense supernode blocks go through BLAS 3, as do the solves of many
///   right-hand sides at once;
/// - "simplicial": Eigen's SimplicialLDLT (AMD ordering), column by column.
class GeneralFactor
{
public:
  virtual ~GeneralFactor() = default;
  /// Symbolic analysis of `pattern` (lower triangle; values ignored)
  virtual void analyze(const bodies::BodyMatrix& pattern) = 0;
  /// Numerical factorization of `A` (lower triangle, `pattern`'s pattern)
  /// @return false if A is not positive definite
  virtual bool factorize(const bodies::BodyMatrix& A) = 0;
  /// Solve A X = Y for one or many right-hand sides (columns of Y)
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& Y) const = 0;
  virtual Eigen::VectorXd solve(const Eigen::VectorXd& y) const = 0;
};

/// A new, empty factor of the given kind ("cholmod": the 3D bodies'; or
/// "simplicial", which the tests compare it with)
std::unique_ptr<GeneralFactor> make_general_factor(const std::string& kind);

} // namespace softpack::dynamics
