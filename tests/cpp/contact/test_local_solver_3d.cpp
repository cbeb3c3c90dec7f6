// The exact 3x3 Signorini–Coulomb solve (circular cone): problems built
// from a chosen exact solution in every regime (open, stick, slide in any
// direction, frictionless), the 2D solver's answer when the second tangent
// is decoupled, and a randomised check that every answer satisfies the law
// (natural-map residual ~ 0).

#include "error.h"
#include "local_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace softpack::contact;

namespace
{
/// A symmetric positive definite block, sometimes far from diagonal
Eigen::Matrix3d random_block(std::mt19937& gen)
{
  std::uniform_real_distribution<double> unit(-1, 1);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i)
    A(i / 3, i % 3) = unit(gen);
  return A * A.transpose() + 1e-2 * Eigen::Matrix3d::Identity();
}

/// Some blocks: diagonal, isotropic, coupled normal-tangent, non-symmetric
std::vector<Eigen::Matrix3d> blocks()
{
  Eigen::Matrix3d coupled, nonsymmetric;
  coupled << 2.0, 0.3, -0.2, 0.3, 1.5, 0.4, -0.2, 0.4, 1.2;
  nonsymmetric = coupled;
  nonsymmetric(0, 1) += 0.05; // as a Rover4144 block: W_nt != W_tn
  nonsymmetric(2, 1) -= 0.03;
  return {Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 3, 0.5).asDiagonal(),
          coupled, nonsymmetric};
}

double residual(const Eigen::Matrix3d& W, const Eigen::Vector3d& q, double mu,
                const Eigen::Vector3d& r)
{
  return natural_map_residual_squared(r, Eigen::Vector3d(W * r + q), mu);
}

/// The solve of q = u - W r for a chosen exact (r, u) gives r back
void expect_solution(const Eigen::Matrix3d& W, const Eigen::Vector3d& r,
                     const Eigen::Vector3d& u, double mu, ContactStatus status)
{
  const Eigen::Vector3d q = u - W * r;
  const LocalSolution3D s = solve_local(W, q, mu);
  EXPECT_EQ(s.status, status) << "r " << r.transpose();
  EXPECT_LT((s.r - r).norm(), 1e-12 * (1 + r.norm())) << s.r.transpose();
  EXPECT_LT(residual(W, q, mu, s.r), 1e-26 * (1 + q.squaredNorm()));
}
} // namespace

TEST(LocalSolver3D, OpenContactHasNoReaction)
{
  for (const Eigen::Matrix3d& W : blocks())
  {
    const LocalSolution3D s = solve_local(W, {0.2, -1, 3}, 0.5);
    EXPECT_EQ(s.status, ContactStatus::separated);
    EXPECT_EQ(s.r, Eigen::Vector3d::Zero());
    // grazing: q_n = 0 is open too (r = 0 satisfies the law)
    EXPECT_EQ(solve_local(W, {0, 1, 1}, 0.5).r, Eigen::Vector3d::Zero());
  }
}

TEST(LocalSolver3D, StickInsideTheCone)
{
  const double mu = 0.5;
  for (const Eigen::Matrix3d& W : blocks())
    for (const Eigen::Vector3d& r :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 0.3, -0.6),
          Eigen::Vector3d(1, -0.35, 0.35)})
      expect_solution(W, r, Eigen::Vector3d::Zero(), mu, ContactStatus::stick);
}

TEST(LocalSolver3D, SlideInEveryDirection)
{
  // r = r_n (1, -mu s) on the cone's edge, u = (0, alpha s), alpha > 0
  for (const Eigen::Matrix3d& W : blocks())
    for (const double mu : {0.1, 0.3, 0.8})
      for (int k = 0; k < 24; ++k)
      {
        const double theta = 2 * std::numbers::pi * (k + 0.3) / 24;
        const Eigen::Vector2d s(std::cos(theta), std::sin(theta));
        const double rn = 1.7, alpha = 0.4 + 0.1 * (k % 5);
        const Eigen::Vector3d r(rn, -mu * rn * s[0], -mu * rn * s[1]);
        const Eigen::Vector3d u(0, alpha * s[0], alpha * s[1]);
        expect_solution(W, r, u, mu, ContactStatus::slide);
      }
}

TEST(LocalSolver3D, FrictionlessAndZeroMu)
{
  for (const Eigen::Matrix3d& W : blocks())
  {
    // mu = 0: r_t = 0, r_n from u_n = 0, any tangential velocity
    const Eigen::Vector3d q(-0.6, 0.3, -2);
    const LocalSolution3D s = solve_local(W, q, 0.0);
    EXPECT_EQ(s.r, Eigen::Vector3d(0.6 / W(0, 0), 0, 0));
    EXPECT_NEAR((W * s.r + q)[0], 0, 1e-15);
    EXPECT_LT(residual(W, q, 0.0, s.r), 1e-30);
  }
}

TEST(LocalSolver3D, DecoupledSecondTangentIsThe2DSolution)
{
  // W = [W2 0; 0 w], q_t2 = 0: the 3D answer is the 2D one with r_t2 = 0
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 500; ++trial)
  {
    Eigen::Matrix2d A;
    A << unit(gen), unit(gen), unit(gen), unit(gen);
    const Eigen::Matrix2d W2 =
        A * A.transpose() + 1e-2 * Eigen::Matrix2d::Identity();
    Eigen::Matrix3d W = Eigen::Matrix3d::Zero();
    W.topLeftCorner<2, 2>() = W2;
    W(2, 2) = 0.5 + unit(gen) * unit(gen);
    const Eigen::Vector2d q2(unit(gen), unit(gen));
    const double mu = 1.0 + unit(gen);
    const LocalSolution s2 = solve_local(W2, q2, mu);
    const LocalSolution3D s3 = solve_local(W, {q2[0], q2[1], 0}, mu);
    EXPECT_LT((s3.r.head<2>() - s2.r).norm(), 1e-11 * (1 + s2.r.norm()))
        << "trial " << trial;
    EXPECT_LT(std::abs(s3.r[2]), 1e-11 * (1 + s2.r.norm()));
  }
}

TEST(LocalSolver3D, EveryAnswerSatisfiesTheLaw)
{
  std::mt19937 gen(2026);
  std::uniform_real_distribution<double> unit(-1, 1), friction(0, 2);
  int closest = 0;
  for (int trial = 0; trial < 20000; ++trial)
  {
    const Eigen::Matrix3d W = random_block(gen);
    const Eigen::Vector3d q(unit(gen), unit(gen), unit(gen));
    const double mu = trial % 10 == 0 ? 0.0 : friction(gen);
    const LocalSolution3D s = solve_local(W, q, mu);
    closest += s.status == ContactStatus::closest;
    const double scale = 1 + s.r.squaredNorm() + q.squaredNorm();
    ASSERT_LT(residual(W, q, mu, s.r), 1e-22 * scale)
        << "trial " << trial << " status " << int(s.status);
    ASSERT_LE(std::hypot(s.r[1], s.r[2]), mu * s.r[0] * (1 + 1e-12) + 1e-300);
  }
  EXPECT_LE(closest, 20); // a branch holds but at rounding boundaries
}

TEST(LocalSolver3D, CohesiveShiftsTheNormalReaction)
{
  // the law in r + c e_n: an open cohesive contact pulls with -c
  const Eigen::Matrix3d W = blocks()[2];
  const double mu = 0.4, c = 0.3;
  const Eigen::Vector3d q(0.5, 0.1, 0.2);
  const LocalSolution3D s = solve_local(W, q, mu, c);
  const Eigen::Vector3d r_shifted = s.r + Eigen::Vector3d(c, 0, 0);
  EXPECT_LT(
      natural_map_residual_squared(r_shifted, Eigen::Vector3d(W * s.r + q), mu),
      1e-28);
  EXPECT_EQ(solve_local(W, q, mu, 0.0).r, solve_local(W, q, mu).r);
}
