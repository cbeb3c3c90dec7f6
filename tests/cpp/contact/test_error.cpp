// The natural-map error with the De Saxcé velocity (Siconos
// fc2d_compute_error) and its q = 0 case.

#include "error.h"
#include "helpers.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace softpack::contact;
using namespace softpack::contact::test;

TEST(Error, ProjectionOnTheCone)
{
  const double mu = 0.5;
  EXPECT_EQ(project_on_cone({2, 0.5}, mu), Eigen::Vector2d(2, 0.5)); // in K
  EXPECT_EQ(project_on_cone({-2, 0.5}, mu), Eigen::Vector2d(0, 0));  // polar
  // outside both: onto the edge r_t = mu r_n, orthogonally
  const Eigen::Vector2d x(1, 3), p = project_on_cone(x, mu);
  EXPECT_NEAR(p[1], mu * p[0], 1e-15);
  EXPECT_NEAR((x - p).dot(Eigen::Vector2d(1, mu)), 0.0, 1e-15);
  EXPECT_NEAR(project_on_cone({1, -3}, mu)[1], -p[1], 1e-15);
  // mu = 0: the half line r_t = 0, r_n >= 0
  EXPECT_EQ(project_on_cone({2, 5}, 0.0), Eigen::Vector2d(2, 0));
  EXPECT_EQ(project_on_cone({-2, 5}, 0.0), Eigen::Vector2d(0, 0));
}

TEST(Error, ZeroExactlyOnTheLaw)
{
  const double mu = 0.3;
  auto res = [mu](Eigen::Vector2d r, Eigen::Vector2d u)
  { return natural_map_residual_squared(r, u, mu); };
  EXPECT_EQ(res({0, 0}, {2, -1}), 0.0);     // open
  EXPECT_EQ(res({1, 0.2}, {0, 0}), 0.0);    // stick
  EXPECT_EQ(res({1, -0.3}, {0, 0.7}), 0.0); // slide, u_t > 0
  EXPECT_EQ(res({1, 0.3}, {0, -0.7}), 0.0); // slide, u_t < 0
  EXPECT_GT(res({0, 0}, {-1, 0}), 0.0);     // penetration
  EXPECT_GT(res({1, 0}, {0.5, 0}), 0.0);    // force while separating
  EXPECT_GT(res({1, 0.5}, {0, 0}), 0.0);    // outside the cone
  EXPECT_GT(res({1, 0.3}, {0, 0.7}), 0.0);  // friction pushes along u_t
}

TEST(Error, RelativeToTheLargestOfRUAndQ)
{
  // one contact, W = 2 I, q = (-2, 0), r = (0.5, 0): u = (-1, 0)
  FrictionContactProblem2D p = make_problem(2 * Eigen::MatrixXd::Identity(2, 2),
                                            Eigen::Vector2d(-2, 0), {0.3});
  std::vector<double> r = {0.5, 0}, u(2);
  const NaturalMapError e = compute_error(p, r, u, 1e-12);
  EXPECT_DOUBLE_EQ(u[0], -1.0);
  // r - proj(r - u~) = (0.5, 0) - (1.5, 0)
  EXPECT_DOUBLE_EQ(e.absolute, 1.0);
  EXPECT_DOUBLE_EQ(e.scale, 2.0);
  EXPECT_DOUBLE_EQ(e.value, 0.5);
  EXPECT_FALSE(e.q_zero);

  r = {1, 0};
  EXPECT_EQ(compute_error(p, r, u, 1e-12).value, 0.0);
}

TEST(Error, QZeroIsAbsolute)
{
  // q is rounding noise: r = 0 is the answer, and the relative error (about
  // 0.68 here) would only measure the noise
  FrictionContactProblem2D p = make_problem(
      Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(-1e-15, 1e-15), {0.3});
  std::vector<double> r = {0, 0}, u(2);
  const NaturalMapError e = compute_error(p, r, u, 1e-12);
  EXPECT_TRUE(e.q_zero);
  EXPECT_EQ(e.value, e.absolute);
  EXPECT_LT(e.value, 1e-15);
  EXPECT_TRUE(is_q_zero(p, 1e-12));
  EXPECT_FALSE(is_q_zero(p, 1e-16));

  const NaturalMapError relative = compute_error(p, r, u, 0.0);
  EXPECT_FALSE(relative.q_zero);
  EXPECT_NEAR(relative.value, e.absolute / std::sqrt(2e-30), 1e-12);
  EXPECT_GT(relative.value, 0.5);
}
