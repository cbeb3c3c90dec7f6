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
/// - "cholmod" (the default): CHOLMOD's supernodal Cholesky LL^T, whose
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

/// The kind of general factors made by make_general_factor(): "cholmod",
/// unless the environment variable SOFTPACK_3D_FACTORS says "simplicial"
/// (a switch kept to compare the two; docs/performance_3d.md).
/// @throws std::invalid_argument for another value
std::string general_factor_kind();

/// A new, empty factor of the given kind ("cholmod" or "simplicial")
std::unique_ptr<GeneralFactor> make_general_factor(const std::string& kind);

} // namespace softpack::dynamics
