#include "problem_structure.h"

#include "coupling_graph.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

using namespace softpack::contact;

namespace
{
//-----------------------------------------------------------------------------
template <int D>
void count_couplings(const DelassusMatrixD<D>& W, ProblemStructure& s)
{
  for (int k = -9; k <= -2; ++k)
    s.coupling_thresholds.push_back(std::pow(10.0, k));
  s.blocks_at_or_above.assign(s.coupling_thresholds.size(), 0);
  std::vector<double> diagonal(W.num_contacts());
  for (std::size_t a = 0; a < W.num_contacts(); ++a)
    diagonal[a] = W.diagonal(a).norm();
  for (std::size_t a = 0; a < W.num_contacts(); ++a)
  {
    const auto columns = W.row_columns(a);
    const auto blocks = W.row_blocks(a);
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
      const double size =
          blocks[k].norm() / std::sqrt(diagonal[a] * diagonal[columns[k]]);
      for (std::size_t t = 0; t < s.coupling_thresholds.size(); ++t)
        s.blocks_at_or_above[t] += size >= s.coupling_thresholds[t];
    }
  }
}
//-----------------------------------------------------------------------------
/// W's normal block over a set, scaled by its diagonal
template <int D>
Eigen::MatrixXd scaled_normal_block(const DelassusMatrixD<D>& W,
                                    const std::vector<std::int32_t>& set)
{
  const auto m = static_cast<Eigen::Index>(set.size());
  std::vector<std::int32_t> local(W.num_contacts(), -1);
  for (Eigen::Index i = 0; i < m; ++i)
    local[set[i]] = static_cast<std::int32_t>(i);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
  {
    B(i, i) = W.diagonal(set[i])(0, 0);
    const auto columns = W.row_columns(set[i]);
    const auto blocks = W.row_blocks(set[i]);
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (local[columns[k]] >= 0)
        B(i, local[columns[k]]) = blocks[k](0, 0);
  }
  const Eigen::VectorXd scale = B.diagonal().cwiseSqrt().cwiseInverse();
  // the mean of W_ab and W_ba: W is symmetric to its blocks' rounding
  const Eigen::MatrixXd S = scale.asDiagonal() * B * scale.asDiagonal();
  return 0.5 * (S + S.transpose());
}
} // namespace
//-----------------------------------------------------------------------------
template <int D>
ProblemStructure
softpack::contact::problem_structure(const FrictionContactProblem<D>& problem)
{
  ProblemStructure s;
  s.contacts = problem.num_contacts();
  s.offdiagonal_blocks = problem.W.num_offdiagonal_blocks();
  count_couplings(problem.W, s);

  const std::vector<std::vector<std::int32_t>> sets =
      frictionless_sets(problem, std::vector<char>(s.contacts));
  for (const std::vector<std::int32_t>& set : sets)
    s.frictionless += set.size();
  s.frictionless_sets = sets.size();
  if (sets.empty())
    return s;
  s.smallest_set = s.largest_set = sets.front().size();
  double lowest = std::numeric_limits<double>::infinity(), highest = 0;
  for (const std::vector<std::int32_t>& set : sets)
  {
    s.smallest_set = std::min(s.smallest_set, set.size());
    s.largest_set = std::max(s.largest_set, set.size());
    if (set.size() > s.largest_conditioned)
      continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
        scaled_normal_block(problem.W, set), Eigen::EigenvaluesOnly);
    lowest = std::min(lowest, eigen.eigenvalues().minCoeff());
    highest = std::max(highest, eigen.eigenvalues().maxCoeff());
  }
  s.scaled_eigenvalue_min = std::isfinite(lowest) ? lowest : 0;
  s.scaled_eigenvalue_max = highest;
  return s;
}
//-----------------------------------------------------------------------------
template ProblemStructure
softpack::contact::problem_structure(const FrictionContactProblem<2>&);
template ProblemStructure
softpack::contact::problem_structure(const FrictionContactProblem<3>&);
