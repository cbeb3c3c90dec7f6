// Every problem of ../shared/data/fclib solved to the error its README calls
// realistic (1e-8; 1e-6 for the granular 02020 problem), by the same code
// the simulator calls.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace softpack::contact;
using namespace softpack::contact::test;

class FclibProblem : public ::testing::TestWithParam<DataProblem>
{
};

TEST_P(FclibProblem, SolvedToTheRealisticError)
{
  const DataProblem& d = GetParam();
  const FclibLocalFile file = read_fclib_local_file(hdf5_file(d.name));
  const FrictionContactProblem2D& p = file.problem;
  EXPECT_EQ(file.title, d.name);

  NlgsOptions opt;
  opt.tolerance = d.tolerance;
  opt.max_sweeps = 10000;
  std::vector<double> r(2 * p.num_contacts(), 0.0), u(r.size());
  const NlgsResult res = solve_nlgs(p, r, u, opt);
  std::cout << "[ fclib    ] " << d.name << ": " << p.num_contacts()
            << " contacts, " << res.iterations << " sweeps, error " << res.error
            << (res.q_zero ? " (q = 0, absolute)" : "") << "\n";
  RecordProperty("sweeps", res.iterations);
  EXPECT_TRUE(res.converged);
  EXPECT_LE(res.error, d.tolerance);
  for (double v : r)
    ASSERT_TRUE(std::isfinite(v));
}

TEST_P(FclibProblem, BlockFormReproducesTheStoredVelocities)
{
  // The file's /solution holds u = W r + q computed with its scalar CSR W:
  // the 2x2 block form read here must give the same product.
  const DataProblem& d = GetParam();
  const FclibLocalFile file = read_fclib_local_file(hdf5_file(d.name));
  ASSERT_TRUE(file.solution_r and file.solution_u);
  const FrictionContactProblem2D& p = file.problem;
  std::vector<double> u(p.q);
  p.W.multiply_add(*file.solution_r, u);
  double scale = 0;
  for (std::size_t k = 0; k < u.size(); ++k)
    scale = std::max({scale, std::abs(u[k]), std::abs(p.q[k])});
  for (std::size_t k = 0; k < u.size(); ++k)
    EXPECT_NEAR(u[k], (*file.solution_u)[k], 1e-12 * scale) << "entry " << k;
}

INSTANTIATE_TEST_SUITE_P(Data, FclibProblem,
                         ::testing::ValuesIn(data_problems()),
                         [](const auto& info) { return info.param.name; });
