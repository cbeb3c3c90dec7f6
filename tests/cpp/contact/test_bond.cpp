// The bonded law (docs/contact_laws.md, law "bonded"): the local solve of
// an intact bond in every regime (bonded stick in tension and compression,
// break in tension, break in shear) against its closed form, the broken
// contact's regimes (open, slide: plain Signorini–Coulomb), the break rule,
// a randomised check, and the NLGS on the FCLIB 2D set: no bond is the
// plain problem bit for bit, bonds on half the contacts are solved to the
// tolerance with each bond's outcome matching its velocity.

#include "bond.h"
#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"
#include "nlgs_helpers.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
Eigen::Matrix2d matrix(double a, double b, double c, double d)
{
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m;
}

/// T = 1, S = 0.5: the envelope |r_t| <= 0.5 (r_n + 1)
const BondStrength unit_bond{1.0, 0.5};
constexpr double eta = 1e-10;

/// The bond's solve: branch, reaction, the shifted law, the outcome
void expect_bond(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                 ContactStatus status, const Eigen::Vector2d& r_expected,
                 BondOutcome outcome)
{
  const LocalSolution s = solve_bond(W, q, unit_bond);
  EXPECT_EQ(s.status, status);
  EXPECT_NEAR(s.r[0], r_expected[0], 1e-14);
  EXPECT_NEAR(s.r[1], r_expected[1], 1e-14);
  const ShiftedCone cone = bond_cone(unit_bond);
  EXPECT_LT(natural_map_residual_squared(shifted_reaction(s.r, cone.cohesion),
                                         W * s.r + q, cone.coefficient),
            1e-28);
  EXPECT_EQ(bond_outcome(s.r, unit_bond, eta), outcome);
}
} // namespace

TEST(BondLocalSolver, TheEnvelopeIsTheShiftedCone)
{
  const ShiftedCone cone = bond_cone({2.0, 3.0});
  EXPECT_EQ(cone.cohesion, 2.0);
  EXPECT_EQ(cone.coefficient, 1.5);
  EXPECT_THROW(bond_cone({0.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(bond_cone({1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(bond_cone({1.0, -1.0}), std::invalid_argument);
  EXPECT_THROW(bond_cone({std::nan(""), 1.0}), std::invalid_argument);
  EXPECT_THROW(bond_outcome({0, 0}, unit_bond, 1.0), std::invalid_argument);
  EXPECT_THROW(bond_outcome({0, 0}, unit_bond, -0.1), std::invalid_argument);
}

TEST(BondLocalSolver, BondedStickInTensionAndCompression)
{
  // r = -W^-1 q = (-0.5, -0.1): tensile, |r_t| = 0.1 < 0.5 (r_n + 1) = 0.25
  expect_bond(matrix(2, 0, 0, 1), {1, 0.1}, ContactStatus::stick, {-0.5, -0.1},
              BondOutcome::holds);
  // r = (1, -0.3), compressive: |r_t| = 0.3 < 0.5 x 2
  expect_bond(matrix(2, 0, 0, 1), {-2, 0.3}, ContactStatus::stick, {1, -0.3},
              BondOutcome::holds);
  // with coupling: r = (-0.2, 0.1) given, q = -W r
  const Eigen::Matrix2d W = matrix(2, 0.3, 0.3, 1);
  const Eigen::Vector2d r(-0.2, 0.1);
  expect_bond(W, -W * r, ContactStatus::stick, r, BondOutcome::holds);
}

TEST(BondLocalSolver, BreakInTension)
{
  // q' = q - T W e_n = (1, 0.2) >= 0: open, pulled by its whole strength
  expect_bond(matrix(2, 0, 0, 1), {3, 0.2}, ContactStatus::separated, {-1, 0},
              BondOutcome::tension);
  // just at the strength: q' = (0, 0.2)
  expect_bond(matrix(2, 0, 0, 1), {2, 0.2}, ContactStatus::separated, {-1, 0},
              BondOutcome::tension);
}

TEST(BondLocalSolver, BreakInShear)
{
  // q' = (-4, 3): stick would need |r_t| = 3 > 0.5 x 2; slide with
  // u_t >= 0, r'_n = 4 / 2 = 2, r_t = -1: r = (1, -1)
  expect_bond(matrix(2, 0, 0, 1), {-2, 3}, ContactStatus::slide_positive,
              {1, -1}, BondOutcome::shear);
  // in tension: q' = (-1.5, -2), r'_n = 0.75, r_t = +0.375: r = (-0.25,
  // 0.375), slide with u_t <= 0
  expect_bond(matrix(2, 0, 0, 1), {0.5, -2}, ContactStatus::slide_negative,
              {-0.25, 0.375}, BondOutcome::shear);
  // with coupling: r'_n = -q'_n / (W_nn - m W_nt)
  const Eigen::Matrix2d W = matrix(2, 0.3, 0.3, 1);
  const Eigen::Vector2d q(-1, 4);
  const double q_n = q[0] - 1.0 * W(0, 0);
  const double rn = -q_n / (W(0, 0) - 0.5 * W(0, 1));
  expect_bond(W, q, ContactStatus::slide_positive, {rn - 1, -0.5 * rn},
              BondOutcome::shear);
}

TEST(BondLocalSolver, BrokenBondIsPlainSignoriniCoulomb)
{
  // after the break the contact is solve_local(W, q, mu): open ...
  const Eigen::Matrix2d W = matrix(2, 0, 0, 1);
  LocalSolution s = solve_local(W, {0.5, 1}, 0.3);
  EXPECT_EQ(s.status, ContactStatus::separated);
  EXPECT_EQ(s.r, Eigen::Vector2d(0, 0));
  // ... or sliding on mu: r_n = 1, r_t = -0.3
  s = solve_local(W, {-2, 3}, 0.3);
  EXPECT_EQ(s.status, ContactStatus::slide_positive);
  EXPECT_NEAR(s.r[0], 1, 1e-15);
  EXPECT_NEAR(s.r[1], -0.3, 1e-15);
}

TEST(BondLocalSolver, BreakRule)
{
  EXPECT_EQ(bond_outcome({-1, 0}, unit_bond, eta), BondOutcome::tension);
  EXPECT_EQ(bond_outcome({-1 + 1e-3, 0}, unit_bond, eta), BondOutcome::holds);
  EXPECT_EQ(bond_outcome({-1 + 1e-3, 0}, unit_bond, 1e-2),
            BondOutcome::tension);
  // on the slope (r_n = 1: |r_t| = 1), just inside it, just outside it
  EXPECT_EQ(bond_outcome({1, 1}, unit_bond, eta), BondOutcome::shear);
  EXPECT_EQ(bond_outcome({1, -1}, unit_bond, eta), BondOutcome::shear);
  EXPECT_EQ(bond_outcome({1, 0.999}, unit_bond, eta), BondOutcome::holds);
  EXPECT_EQ(bond_outcome({1, 0.999}, unit_bond, 1e-2), BondOutcome::shear);
}

TEST(BondLocalSolver, EveryAnswerSatisfiesTheEnvelopeAndTheRule)
{
  std::mt19937 gen(39);
  std::uniform_real_distribution<double> unit(-1, 1), positive(0.01, 2);
  int counts[3] = {0, 0, 0};
  for (int k = 0; k < 100000; ++k)
  {
    Eigen::Matrix2d A;
    A << unit(gen), unit(gen), unit(gen), unit(gen);
    const Eigen::Matrix2d W =
        A * A.transpose() + 1e-3 * Eigen::Matrix2d::Identity();
    const Eigen::Vector2d q(unit(gen), unit(gen));
    const BondStrength b{positive(gen), positive(gen)};
    const ShiftedCone cone = bond_cone(b);
    const LocalSolution s = solve_bond(W, q, b);
    const Eigen::Vector2d u = W * s.r + q;
    ASSERT_GE(s.r[0], -b.tensile);
    ASSERT_LT(natural_map_residual_squared(shifted_reaction(s.r, b.tensile), u,
                                           cone.coefficient),
              1e-20 * (1 + s.r.squaredNorm() + q.squaredNorm()));
    const BondOutcome o = bond_outcome(s.r, b, eta);
    ++counts[static_cast<int>(o)];
    // a bond that holds is stuck (u = 0); one that opens or slides breaks
    if (o == BondOutcome::holds)
      ASSERT_LT(u.norm(), 1e-10 * (1 + q.norm()));
    if (s.status == ContactStatus::separated or
        s.status == ContactStatus::slide_positive or
        s.status == ContactStatus::slide_negative)
      ASSERT_NE(o, BondOutcome::holds);
  }
  std::cout << "[ bond ] holds " << counts[0] << ", tension " << counts[1]
            << ", shear " << counts[2] << " of 100000\n";
  for (int c : counts)
    EXPECT_GT(c, 1000);
}

class BondFclib : public ::testing::TestWithParam<DataProblem>
{
};

TEST_P(BondFclib, NoBondIsThePlainSolveBitForBit)
{
  const DataProblem& d = GetParam();
  const FrictionContactProblem2D plain =
      read_fclib_local_file(hdf5_file(d.name)).problem;
  FrictionContactProblem2D none = plain;
  set_bonds(none, {}, {});
  EXPECT_TRUE(none.cohesion.empty());
  EXPECT_EQ(none.friction, plain.friction);
  expect_the_same_solves(plain, none, d.tolerance, 20000);
}

TEST_P(BondFclib, BondsOnHalfTheContacts)
{
  // Every other contact bonded, T = 0.2 |q|_inf / (W_aa)_nn (of the order
  // of the problem's impulses, so that bonds both hold and break), S = T/2
  const DataProblem& d = GetParam();
  FrictionContactProblem2D p = read_fclib_local_file(hdf5_file(d.name)).problem;
  const std::size_t nc = p.num_contacts();
  const double q_max = largest_free_velocity(p);
  std::vector<std::int32_t> bonded;
  std::vector<BondStrength> strengths;
  for (std::size_t a = 0; a < nc; a += 2)
  {
    const double T = 0.2 * q_max / p.W.diagonal(a)(0, 0);
    bonded.push_back(static_cast<std::int32_t>(a));
    strengths.push_back({T, 0.5 * T});
  }
  set_bonds(p, bonded, strengths);
  validate(p);
  const Solve s = solve(p, options(d.tolerance, 1.7, 20000));
  EXPECT_TRUE(s.result.converged) << s.result.error;
  if (s.result.q_zero) // |q| <= 1e-12 (two of the set): r = 0, no sweep
  {
    EXPECT_EQ(s.r, std::vector<double>(2 * nc, 0.0));
    return;
  }
  // a bond that holds has u ~ 0 (to the solve's tolerance, relative to the
  // problem's scale); the others are on their envelope by bond_outcome
  double scale = q_max, worst = 0;
  for (double v : s.u)
    scale = std::max(scale, std::abs(v));
  int counts[3] = {0, 0, 0};
  for (std::size_t k = 0; k < bonded.size(); ++k)
  {
    const std::size_t a = bonded[k];
    const BondOutcome o = bond_outcome({s.r[2 * a], s.r[2 * a + 1]},
                                       strengths[k], 10 * d.tolerance);
    ++counts[static_cast<int>(o)];
    if (o == BondOutcome::holds)
      worst = std::max(worst, std::hypot(s.u[2 * a], s.u[2 * a + 1]) / scale);
  }
  std::cout << "[ bond ] " << d.name << ": " << s.result.iterations
            << " sweeps, error " << s.result.error << "; bonds: holds "
            << counts[0] << ", tension " << counts[1] << ", shear " << counts[2]
            << "; largest |u| of a holding bond / scale " << worst << "\n";
  EXPECT_LE(worst, 100 * d.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Data, BondFclib, ::testing::ValuesIn(data_problems()),
                         [](const auto& info) { return info.param.name; });
