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

TEST_P(FclibProblem, OverRelaxedSolveStillConverges)
{
  // omega = 1.8 cuts the sweeps on deformable-body problems several times;
  // where it would not converge (rigid granular problems), the solver drops
  // back to omega = 1 and still reaches the realistic error.
  const DataProblem& d = GetParam();
  const FclibLocalFile file = read_fclib_local_file(hdf5_file(d.name));
  NlgsOptions opt;
  opt.tolerance = d.tolerance;
  opt.max_sweeps = 10000;
  opt.relaxation = 1.8;
  std::vector<double> r(2 * file.problem.num_contacts(), 0.0), u(r.size());
  const NlgsResult res = solve_nlgs(file.problem, r, u, opt);
  std::cout << "[ fclib    ] " << d.name << ", omega 1.8: " << res.iterations
            << " sweeps" << (res.relaxation_dropped ? " (dropped to 1)" : "")
            << ", error " << res.error << "\n";
  EXPECT_TRUE(res.converged);
  EXPECT_LE(res.error, d.tolerance);
}

TEST(FclibProblemRelaxation, WithoutTheFallbackTheGranularProblemFails)
{
  // Why the fallback exists: plain over-relaxation does not converge on the
  // 2020-contact granular problem.
  const FclibLocalFile file =
      read_fclib_local_file(hdf5_file("fc2d_granularflowonwall_02020_00213"));
  NlgsOptions opt;
  opt.tolerance = 1e-6;
  opt.max_sweeps = 5000;
  opt.relaxation = 1.8;
  opt.relaxation_window = 0;
  std::vector<double> r(2 * file.problem.num_contacts(), 0.0), u(r.size());
  EXPECT_FALSE(solve_nlgs(file.problem, r, u, opt).converged);
  opt.relaxation_window = 50;
  std::fill(r.begin(), r.end(), 0.0);
  const NlgsResult res = solve_nlgs(file.problem, r, u, opt);
  EXPECT_TRUE(res.converged);
  EXPECT_TRUE(res.relaxation_dropped);
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
