// The NLGS with cohesive contacts (docs/contact_laws.md): c = 0 given as a
// vector is the plain solve bit for bit on the FCLIB 2D set; a cohesive
// problem is the plain problem of the shifted reactions r' = r + c e_n,
// whose free velocity is q' = q - W c e_n; and a manufactured problem with
// an open and an adhesive contact.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"
#include "nlgs_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace softpack::contact;
using namespace softpack::contact::test;

class CohesiveFclib : public ::testing::TestWithParam<DataProblem>
{
};

TEST_P(CohesiveFclib, ZeroCohesionIsThePlainSolveBitForBit)
{
  const DataProblem& d = GetParam();
  const FrictionContactProblem2D plain =
      read_fclib_local_file(hdf5_file(d.name)).problem;
  FrictionContactProblem2D zero = plain;
  zero.cohesion.assign(plain.num_contacts(), 0.0);
  expect_the_same_solves(plain, zero, d.tolerance);
}

TEST_P(CohesiveFclib, CohesionIsTheShiftedPlainProblem)
{
  // c_a = 0.2 |q|_inf / (W_aa)_nn: of the order of the impulses of the
  // problem, so that many contacts turn tensile
  const DataProblem& d = GetParam();
  FrictionContactProblem2D p = read_fclib_local_file(hdf5_file(d.name)).problem;
  const std::size_t nc = p.num_contacts();
  const double q_max = largest_free_velocity(p);
  p.cohesion.resize(nc);
  std::vector<double> c_vector(2 * nc, 0.0);
  for (std::size_t a = 0; a < nc; ++a)
    c_vector[2 * a] = p.cohesion[a] = 0.2 * q_max / p.W.diagonal(a)(0, 0);
  validate(p);
  FrictionContactProblem2D shifted = p;
  shifted.cohesion.clear();
  for (double& v : shifted.q)
    v = -v;
  shifted.W.multiply_add(c_vector, shifted.q); // W c - q
  for (double& v : shifted.q)
    v = -v;

  const NlgsOptions opt = options(d.tolerance, 1.7);
  const Solve s = solve(p, opt);
  EXPECT_TRUE(s.result.converged) << s.result.error;
  // (r + c, u) against the plain shifted problem, by its own error
  std::vector<double> r_shifted(s.r), u(2 * nc);
  int tensile = 0;
  for (std::size_t a = 0; a < nc; ++a)
  {
    r_shifted[2 * a] += p.cohesion[a];
    tensile += s.r[2 * a] < 0;
  }
  const NaturalMapError e =
      compute_error(shifted, r_shifted, u, opt.q_zero_tolerance);
  std::cout << "[ cohesive ] " << d.name << ": " << s.result.iterations
            << " sweeps, error " << s.result.error << ", shifted problem's "
            << e.value << ", " << tensile << " of " << nc << " tensile\n";
  // the two errors differ by their scales only (|r| against |r + c|, |q|
  // against |q'|): the shifted problem's error measured 0.35 to 0.89 of
  // the tolerance on this set (2026-12-03)
  EXPECT_LE(e.value, 3 * d.tolerance);
  for (std::size_t k = 0; k < u.size(); ++k)
    EXPECT_NEAR(u[k], s.u[k], 1e-12 * (1 + q_max)) << "entry " << k;
}

INSTANTIATE_TEST_SUITE_P(Data, CohesiveFclib,
                         ::testing::ValuesIn(data_problems()),
                         [](const auto& info) { return info.param.name; });

TEST(CohesiveNlgs, ManufacturedOpenAndAdhesiveContacts)
{
  // Two coupled contacts: the first open (u_n > 0) pulled by its whole
  // cohesion, r = (-c, 0); the second stuck with a tensile r_n = -0.2 and
  // |r_t| = 0.05 <= mu (r_n + c) = 0.09
  Eigen::MatrixXd W(4, 4);
  W << 2.0, 0.2, 0.3, 0.1,   //
      0.2, 1.0, -0.05, 0.2,  //
      0.3, -0.05, 1.5, -0.1, //
      0.1, 0.2, -0.1, 0.8;
  const Eigen::Vector4d r(-0.4, 0, -0.2, 0.05), u(0.5, 0.2, 0, 0);
  FrictionContactProblem2D p = make_problem(W, u - W * r, {0.3, 0.3});
  p.cohesion = {0.4, 0.5};
  validate(p);
  const Solve s = solve(p, options(1e-12, 1.0));
  EXPECT_TRUE(s.result.converged);
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(s.r[k], r[k], 1e-11) << "entry " << k;
}

TEST(CohesiveNlgs, ValidateRefusesABadCohesion)
{
  FrictionContactProblem2D p =
      make_problem(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, 0), {0.3});
  p.cohesion = {-1};
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.cohesion = {1, 2};
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.cohesion = {std::nan("")};
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.cohesion = {0.5};
  EXPECT_NO_THROW(validate(p));
}

TEST(CohesiveNlgs, ADumpedCohesiveProblemReadsBackWithItsCohesion)
{
  // An unsolved cohesive problem of a run is written for replay
  // (./softpack fclib FILE): its cohesion travels in vectors/cohesion,
  // and a plain problem's file has none
  TempDir dir;
  FrictionContactProblem2D p =
      read_fclib_local(hdf5_file("FrictionContactProblem00071"));
  EXPECT_TRUE(p.cohesion.empty());
  for (std::size_t a = 0; a < p.num_contacts(); ++a)
    p.cohesion.push_back(0.01 * static_cast<double>(a));
  const std::filesystem::path path = dir.path() / "cohesive.hdf5";
  dump_problem(p, path);
  const FrictionContactProblem2D back = read_fclib_local(path);
  EXPECT_EQ(back.cohesion, p.cohesion);
  EXPECT_EQ(back.q, p.q);
  const NlgsOptions opt = options(1e-8, 1.0);
  EXPECT_EQ(solve(back, opt).r, solve(p, opt).r);
}
