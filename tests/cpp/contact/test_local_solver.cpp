// The exact 2x2 Signorini–Coulomb solve: hand-made cases with known answers
// and a randomised check that every answer satisfies the law; the same for
// a cohesive contact (docs/contact_laws.md) in every regime (open, adhesive
// stick, slide with a tensile reaction, break).

#include "error.h"
#include "local_solver.h"

#include <gtest/gtest.h>

#include <random>

using namespace softpack::contact;

namespace
{
Eigen::Matrix2d matrix(double a, double b, double c, double d)
{
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m;
}

/// A symmetric positive definite block, sometimes far from diagonal
Eigen::Matrix2d random_block(std::mt19937& gen)
{
  std::uniform_real_distribution<double> unit(-1, 1);
  Eigen::Matrix2d A;
  A << unit(gen), unit(gen), unit(gen), unit(gen);
  return A * A.transpose() + 1e-3 * Eigen::Matrix2d::Identity();
}

/// Checks the branch, the reaction and that (r, u) satisfies the law.
void expect_solution(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                     double mu, ContactStatus status,
                     const Eigen::Vector2d& r_expected)
{
  const LocalSolution s = solve_local(W, q, mu);
  EXPECT_EQ(s.status, status);
  EXPECT_NEAR(s.r[0], r_expected[0], 1e-14);
  EXPECT_NEAR(s.r[1], r_expected[1], 1e-14);
  EXPECT_LT(natural_map_residual_squared(s.r, W * s.r + q, mu), 1e-28);
}

/// The branch and the reaction, and that (r + c e_n, u) satisfies the
/// Signorini–Coulomb law with u = W r + q.
void expect_cohesive(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                     double mu, double c, ContactStatus status,
                     const Eigen::Vector2d& r_expected)
{
  const LocalSolution s = solve_local(W, q, mu, c);
  EXPECT_EQ(s.status, status);
  EXPECT_NEAR(s.r[0], r_expected[0], 1e-14);
  EXPECT_NEAR(s.r[1], r_expected[1], 1e-14);
  EXPECT_GE(s.r[0], -c);
  EXPECT_LT(
      natural_map_residual_squared(shifted_reaction(s.r, c), W * s.r + q, mu),
      1e-28);
}
} // namespace

TEST(LocalSolver, OpenContact)
{
  // q_n > 0: the contact separates whatever q_t is
  expect_solution(matrix(2, 0.3, 0.3, 1), {0.5, -1}, 0.5,
                  ContactStatus::separated, {0, 0});
  // q_n = 0: grazing, r = 0 still solves it (u_n = 0, r_n = 0)
  expect_solution(matrix(2, 0, 0, 1), {0, 3}, 0.5, ContactStatus::separated,
                  {0, 0});
}

TEST(LocalSolver, Stick)
{
  // W r = -q gives r = (1, -0.1), inside the cone |r_t| <= 0.5 r_n
  expect_solution(matrix(2, 0, 0, 1), {-2, 0.1}, 0.5, ContactStatus::stick,
                  {1, -0.1});
  // on the cone's edge: |r_t| = mu r_n exactly still sticks
  expect_solution(matrix(2, 0, 0, 1), {-2, 0.5}, 0.5, ContactStatus::stick,
                  {1, -0.5});
}

TEST(LocalSolver, SlideBothWays)
{
  // stick would need r_t = -1 > 0.3 r_n: slides with u_t = 0.7 > 0
  expect_solution(matrix(2, 0, 0, 1), {-2, 1}, 0.3,
                  ContactStatus::slide_positive, {1, -0.3});
  expect_solution(matrix(2, 0, 0, 1), {-2, -1}, 0.3,
                  ContactStatus::slide_negative, {1, 0.3});
  const LocalSolution s = solve_local(matrix(2, 0, 0, 1), {-2, 1}, 0.3);
  const Eigen::Vector2d u = matrix(2, 0, 0, 1) * s.r + Eigen::Vector2d(-2, 1);
  EXPECT_NEAR(u[0], 0.0, 1e-15);
  EXPECT_NEAR(u[1], 0.7, 1e-15);
}

TEST(LocalSolver, SlideWithNormalTangentCoupling)
{
  // W_nt != 0: stick gives r = (2, -4.5)/1.75, outside the cone; sliding
  // with u_t > 0 gives r_n = 1 / (W_nn - mu W_nt) = 1 / 1.8
  const Eigen::Matrix2d W = matrix(2, 0.5, 0.5, 1);
  expect_solution(W, {-1, 2}, 0.4, ContactStatus::slide_positive,
                  {1 / 1.8, -0.4 / 1.8});
  // the mirror case slides the other way: r_n = 1 / (W_nn + mu W_nt)
  expect_solution(matrix(2, -0.5, -0.5, 1), {-1, -2}, 0.4,
                  ContactStatus::slide_negative, {1 / 1.8, 0.4 / 1.8});
}

TEST(LocalSolver, Frictionless)
{
  // mu = 0: r_t = 0 and r_n = -q_n / W_nn, any tangential velocity
  for (double qt : {-3.0, 0.0, 2.0})
  {
    const LocalSolution s = solve_local(matrix(4, 1, 1, 2), {-2, qt}, 0.0);
    EXPECT_DOUBLE_EQ(s.r[0], 0.5);
    EXPECT_EQ(s.r[1], 0.0);
  }
  expect_solution(matrix(4, 1, 1, 2), {1, 5}, 0.0, ContactStatus::separated,
                  {0, 0});
}

TEST(LocalSolver, EveryAnswerSatisfiesTheLaw)
{
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> unit(-1, 1), friction(0, 1.5);
  int closest = 0;
  const int trials = 100000;
  for (int k = 0; k < trials; ++k)
  {
    const Eigen::Matrix2d W = random_block(gen);
    const Eigen::Vector2d q(unit(gen), unit(gen));
    const double mu = k % 10 == 0 ? 0.0 : friction(gen);
    const LocalSolution s = solve_local(W, q, mu);
    const Eigen::Vector2d u = W * s.r + q;
    const double scale = std::max({s.r.norm(), u.norm(), q.norm()});
    ASSERT_LT(std::sqrt(natural_map_residual_squared(s.r, u, mu)),
              1e-12 * scale)
        << "W =\n"
        << W << "\nq = " << q.transpose() << " mu = " << mu;
    closest += s.status == ContactStatus::closest;
  }
  // rounding at a branch boundary is rare
  EXPECT_LT(closest, trials / 1000);
}

TEST(CohesiveLocalSolver, OpenContactPulledByTheWholeCohesion)
{
  // q' = q - c W e_n = (3 - 2, -1) has q'_n > 0: the contact opens
  // (u_n = 1 > 0) and the reaction is the full tension r = (-c, 0), no
  // friction (|r_t| <= mu (r_n + c) = 0)
  expect_cohesive(matrix(2, 0, 0, 1), {3, -1}, 0.5, 1.0,
                  ContactStatus::separated, {-1, 0});
  const LocalSolution s = solve_local(matrix(2, 0, 0, 1), {3, -1}, 0.5, 1.0);
  EXPECT_DOUBLE_EQ((matrix(2, 0, 0, 1) * s.r)[0] + 3, 1.0);
}

TEST(CohesiveLocalSolver, AdhesiveStickHoldsATensileReaction)
{
  // q = (1, 0.1) opens a plain contact; with c = 1, q' = (-1, 0.1) and
  // r' = -W^-1 q' = (0.5, -0.1), inside the cone: r = (-0.5, -0.1), a
  // tension of half the cohesion held with u = 0, and a tangential
  // reaction that plain Coulomb (r_n < 0) would forbid
  expect_cohesive(matrix(2, 0, 0, 1), {1, 0.1}, 0.5, 1.0, ContactStatus::stick,
                  {-0.5, -0.1});
  const Eigen::Vector2d u =
      matrix(2, 0, 0, 1) *
          solve_local(matrix(2, 0, 0, 1), {1, 0.1}, 0.5, 1.0).r +
      Eigen::Vector2d(1, 0.1);
  EXPECT_NEAR(u.norm(), 0.0, 1e-15);
  // a compressive stick with a cohesion: r_n = c W_nn... r' = -W^-1 q'
  // = (1.5, 0), r = (0.5, 0)
  expect_cohesive(matrix(2, 0, 0, 1), {-1, 0}, 0.5, 1.0, ContactStatus::stick,
                  {0.5, 0});
}

TEST(CohesiveLocalSolver, SlideWithTheConeShiftedByTheCohesion)
{
  // q' = (-1, 1): stick would need |r'_t| = 1 > mu r'_n = 0.25; slides with
  // u_t > 0: r'_n = -q'_n / W_nn = 0.5, r_t = -mu r'_n, so r = (-0.5,
  // -0.25): a tensile contact that slides at |r_t| = mu (r_n + c)
  expect_cohesive(matrix(2, 0, 0, 1), {1, 1}, 0.5, 1.0,
                  ContactStatus::slide_positive, {-0.5, -0.25});
  expect_cohesive(matrix(2, 0, 0, 1), {1, -1}, 0.5, 1.0,
                  ContactStatus::slide_negative, {-0.5, 0.25});
  // W_nt != 0: q' = q - c W e_n = (-1, 0.7); r'_n = -q'_n / (W_nn - mu
  // W_nt) = 1 / 1.85
  expect_cohesive(matrix(2, 0.3, 0.3, 1), {1, 1}, 0.5, 1.0,
                  ContactStatus::slide_positive, {1 / 1.85 - 1, -0.5 / 1.85});
}

TEST(CohesiveLocalSolver, BreakBeyondTheCohesiveDistanceIsPlainSignorini)
{
  // The caller gives c = 0 once the gap exceeds the cohesive distance: the
  // stick case above then separates (r = 0), and c = 0 is solve_local()
  // itself, bit for bit
  expect_cohesive(matrix(2, 0, 0, 1), {1, 0.1}, 0.5, 0.0,
                  ContactStatus::separated, {0, 0});
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int k = 0; k < 1000; ++k)
  {
    const Eigen::Matrix2d W = random_block(gen);
    const Eigen::Vector2d q(unit(gen), unit(gen));
    const LocalSolution plain = solve_local(W, q, 0.4);
    const LocalSolution zero = solve_local(W, q, 0.4, 0.0);
    ASSERT_EQ(plain.r[0], zero.r[0]);
    ASSERT_EQ(plain.r[1], zero.r[1]);
    ASSERT_EQ(plain.status, zero.status);
  }
}

TEST(CohesiveLocalSolver, EveryAnswerSatisfiesTheShiftedLaw)
{
  std::mt19937 gen(43);
  std::uniform_real_distribution<double> unit(-1, 1), friction(0, 1.5),
      cohesion(0, 2);
  int tensile = 0;
  const int trials = 100000;
  for (int k = 0; k < trials; ++k)
  {
    const Eigen::Matrix2d W = random_block(gen);
    const Eigen::Vector2d q(unit(gen), unit(gen));
    const double mu = k % 10 == 0 ? 0.0 : friction(gen);
    const double c = cohesion(gen);
    const LocalSolution s = solve_local(W, q, mu, c);
    const Eigen::Vector2d u = W * s.r + q;
    const double scale = std::max({s.r.norm(), u.norm(), q.norm(), c});
    ASSERT_LT(std::sqrt(natural_map_residual_squared(shifted_reaction(s.r, c),
                                                     u, mu)),
              1e-12 * scale)
        << "W =\n"
        << W << "\nq = " << q.transpose() << " mu = " << mu << " c = " << c;
    ASSERT_GE(s.r[0], -c * (1 + 1e-15));
    tensile += s.r[0] < 0;
  }
  // the random cases reach the tensile branches often
  EXPECT_GT(tensile, trials / 10);
}
