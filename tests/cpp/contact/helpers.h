#pragma once

// Shared helpers of the contact tests.

#include "problem.h"

#include <Eigen/Dense>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <temp_dir.h>
#include <vector>

namespace softpack::contact::test
{

/// The FCLIB 2D set (../shared/data/fclib), from the build configuration.
inline std::filesystem::path data_dir()
{
  return SOFTPACK_FCLIB_DATA_DIR;
}

/// One problem of the set and the error its README calls realistic.
struct DataProblem
{
  std::string name;
  double tolerance;
};

/// All problems of the set (README table).
inline std::vector<DataProblem> data_problems()
{
  return {{"FC2D_SliderCrankLagrangian00000", 1e-8},
          {"FrictionContactProblem00031", 1e-8},
          {"FrictionContactProblem00071", 1e-8},
          {"FrictionContactProblem00237", 1e-8},
          {"FrictionContactProblem00374", 1e-8},
          {"FrictionContactProblem00394", 1e-8},
          {"fc2d_granularflowonwall_00667_00000", 1e-8},
          {"fc2d_granularflowonwall_02020_00213", 1e-6},
          {"gfc2d_granularflowonwall_00069_00350", 1e-8}};
}

/// @return data_dir()/hdf5/NAME.hdf5
inline std::filesystem::path hdf5_file(const std::string& name)
{
  return data_dir() / "hdf5" / (name + ".hdf5");
}

/// Build a problem from a dense W (2 nc x 2 nc), storing the nonzero blocks.
inline FrictionContactProblem2D make_problem(const Eigen::MatrixXd& W,
                                             const Eigen::VectorXd& q,
                                             const std::vector<double>& mu)
{
  const std::size_t nc = mu.size();
  FrictionContactProblem2D p;
  p.W = DelassusMatrix(nc);
  for (std::size_t a = 0; a < nc; ++a)
    for (std::size_t b = 0; b < nc; ++b)
    {
      const Eigen::Matrix2d block = W.block<2, 2>(2 * a, 2 * b);
      if (a == b or !block.isZero(0))
        p.W.add_block(a, b, block);
    }
  p.W.finalize();
  p.q.assign(q.data(), q.data() + q.size());
  p.friction = mu;
  return p;
}

/// Dense copy of a block-sparse W (tests only).
inline Eigen::MatrixXd to_dense(const DelassusMatrix& W)
{
  const std::size_t nc = W.num_contacts();
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(2 * nc, 2 * nc);
  for (std::size_t a = 0; a < nc; ++a)
  {
    dense.block<2, 2>(2 * a, 2 * a) = W.diagonal(a);
    const auto cols = W.row_columns(a);
    const auto blocks = W.row_blocks(a);
    for (std::size_t k = 0; k < cols.size(); ++k)
      dense.block<2, 2>(2 * a, 2 * cols[k]) = blocks[k];
  }
  return dense;
}

using softpack::test::TempDir;

} // namespace softpack::contact::test
