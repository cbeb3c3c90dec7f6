#include "held_set.h"

#include <Eigen/Eigenvalues>
#include <stdexcept>
#include <string>

using namespace softpack::contact;

namespace
{
template <int D>
void add_blocks(const HeldSet& s, std::span<const std::int32_t> place,
                DelassusMatrixD<D>& reduced_W,
                std::vector<typename DelassusMatrixD<D>::Block>& diagonal)
{
  const Eigen::MatrixXd correction = s.C * s.X;
  const auto np = static_cast<Eigen::Index>(s.neighbours.size());
  for (Eigen::Index k = 0; k < np; ++k)
    for (Eigen::Index l = 0; l < np; ++l)
      if (k == l)
        diagonal[place[s.neighbours[k]]] -=
            correction.template block<D, D>(D * k, D * k);
      else
        reduced_W.add_block(place[s.neighbours[k]], place[s.neighbours[l]],
                            -correction.template block<D, D>(D * k, D * l));
}

template <int D>
void add_terms(const HeldSet& s, std::span<const std::int32_t> place,
               DelassusMatrixD<D>& reduced_W,
               std::vector<typename DelassusMatrixD<D>::Block>& diagonal)
{
  // C W_SS^-1 C^T = Z^T D^-1 Z with Z = L^-1 P C^T: term k is row k of Z
  // with the factor -1/D_k
  Eigen::MatrixXd Z = s.ldlt.transpositionsP() * s.C.transpose();
  s.ldlt.matrixL().solveInPlace(Z);
  const Eigen::VectorXd inverse_d = s.ldlt.vectorD().cwiseInverse();
  const auto np = static_cast<Eigen::Index>(s.neighbours.size());
  std::vector<std::int32_t> contacts(s.neighbours.size());
  for (Eigen::Index l = 0; l < np; ++l)
  {
    contacts[l] = place[s.neighbours[l]];
    const auto Zl = Z.middleCols(D * l, D);
    diagonal[contacts[l]] -= Zl.transpose() * inverse_d.asDiagonal() * Zl;
  }
  std::vector<typename DelassusMatrixD<D>::Vector> g(s.neighbours.size());
  for (Eigen::Index k = 0; k < Z.rows(); ++k)
  {
    for (Eigen::Index l = 0; l < np; ++l)
      g[l] = Z.row(k).segment(D * l, D).transpose();
    reduced_W.add_rank_one(contacts, g, -inverse_d(k), false,
                           DelassusMatrixD<D>::Reach::local);
  }
}
} // namespace

void HeldSet::factor(const Eigen::MatrixXd& N, const Eigen::MatrixXd& B)
{
  ldlt.compute(0.5 * (N + N.transpose()));
  if (ldlt.info() != Eigen::Success or (ldlt.vectorD().array() <= 0).any())
    throw std::runtime_error(
        "FrictionlessCondensation: a held set's normal block of W is not "
        "positive definite (" +
        std::to_string(N.rows()) + " contacts)");
  X = ldlt.solve(B);
}

template <int D>
void HeldSet::subtract_correction(
    std::span<const std::int32_t> place, DelassusMatrixD<D>& reduced_W,
    std::vector<typename DelassusMatrixD<D>::Block>& diagonal) const
{
  if (as_terms())
    add_terms(*this, place, reduced_W, diagonal);
  else
    add_blocks(*this, place, reduced_W, diagonal);
}

template <int D>
Eigen::Matrix<double, D, D>
softpack::contact::definite(const Eigen::Matrix<double, D, D>& block)
{
  using Block = Eigen::Matrix<double, D, D>;
  const Block sym = 0.5 * (block + block.transpose());
  const double floor = 1e-10 * sym.trace();
  const Eigen::SelfAdjointEigenSolver<Block> eigen(sym);
  if (eigen.eigenvalues()(0) >= floor)
    return block;
  const Eigen::Matrix<double, D, 1> raised =
      eigen.eigenvalues().cwiseMax(floor);
  return eigen.eigenvectors() * raised.asDiagonal() *
             eigen.eigenvectors().transpose() +
         0.5 * (block - block.transpose());
}

template void
HeldSet::subtract_correction<2>(std::span<const std::int32_t>,
                                DelassusMatrixD<2>&,
                                std::vector<DelassusMatrixD<2>::Block>&) const;
template void
HeldSet::subtract_correction<3>(std::span<const std::int32_t>,
                                DelassusMatrixD<3>&,
                                std::vector<DelassusMatrixD<3>::Block>&) const;
template Eigen::Matrix<double, 2, 2>
softpack::contact::definite<2>(const Eigen::Matrix<double, 2, 2>&);
template Eigen::Matrix<double, 3, 3>
softpack::contact::definite<3>(const Eigen::Matrix<double, 3, 3>&);
