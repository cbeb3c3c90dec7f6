// The servo law on plane walls (issue 40): the one ServoStep of 2D, its
// coupling of dimension 3, and the area a pressure acts on.
#include <gtest/gtest.h>
#include <walls/servo_walls.h>
#include <walls/walls.h>

namespace
{
using namespace softpack::dynamics;

/// A 0.04 x 0.03 x 0.02 m box of six planes, the right one a servo wall
std::vector<Wall3D> box()
{
  std::vector<Wall3D> w = {
      {"left", {0, 0, 0}, {1, 0, 0}},   {"right", {0.04, 0, 0}, {-1, 0, 0}},
      {"bottom", {0, 0, 0}, {0, 1, 0}}, {"top", {0, 0.03, 0}, {0, -1, 0}},
      {"base", {0, 0, 0}, {0, 0, 1}},   {"lid", {0, 0, 0.02}, {0, 0, -1}}};
  w[1].control = WallControl::pressure;
  w[1].pressure = 1000;
  w[1].mass = 0.5;
  return w;
}
} // namespace

TEST(ServoWalls3D, APressurePushesWithItsWallsCurrentArea)
{
  std::vector<Wall3D> walls = box();
  link_walls(walls);
  EXPECT_EQ(walls[1].span, (std::array<int, 4>{2, 3, 4, 5}));
  EXPECT_DOUBLE_EQ(wall_area(walls, 1), 0.03 * 0.02);
  EXPECT_DOUBLE_EQ(imposed_force(walls, 1), 1000 * 0.03 * 0.02);
  walls[3].point[1] = 0.025; // the top moves in: the area follows
  EXPECT_DOUBLE_EQ(imposed_force(walls, 1), 1000 * 0.025 * 0.02);
  walls[1].control = WallControl::force;
  walls[1].force = 2.5; // (N in 3D)
  EXPECT_EQ(imposed_force(walls, 1), 2.5);
}

TEST(ServoWalls3D, APressureWithoutTwoFacingPairsOrAMassIsRefused)
{
  std::vector<Wall3D> walls = box();
  walls.resize(4); // no base and lid: one pair only
  EXPECT_THROW(link_walls(walls), std::invalid_argument);
  walls = box();
  walls[1].mass = 0;
  EXPECT_THROW(link_walls(walls), std::invalid_argument);
}

TEST(ServoWalls3D, TheStepFollowsTheOneServoLaw)
{
  // One wall, two contacts coupled by g = frame^T n: V+ = V_free -
  // (1/m) sum g . R, V_mid = th V+ + (1 - th) V-, the energy terms of 2D
  const double h = 1e-3, th = 0.55, m = 0.5, F = 2.0, v0 = -0.1;
  ServoStep s = ServoStep::start(1, F, m, v0, h);
  EXPECT_DOUBLE_EQ(s.v_free, v0 + h * F / m);
  WallCouplingD<3> c;
  c.inverse_mass = 1 / m;
  c.contacts = {0, 2};
  c.g = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.6, 0.8, 0)};
  const std::vector<double> R = {1e-3, 5e-4, 0, 9, 9, 9, 2e-3, 1e-3, 3e-4};
  s.finish<3>(c, R, th);
  const double impulse = 1e-3 + (0.6 * 2e-3 + 0.8 * 1e-3);
  EXPECT_DOUBLE_EQ(s.v_new, s.v_free - impulse / m);
  EXPECT_DOUBLE_EQ(s.v_mid, th * s.v_new + (1 - th) * v0);
  EXPECT_DOUBLE_EQ(s.transmitted<3>(c, R), s.v_mid * impulse);
  EnergyBalance e;
  EXPECT_DOUBLE_EQ(s.account(e, h, th), h * F * s.v_mid);
  EXPECT_DOUBLE_EQ(e.numerical,
                   (th - 0.5) * m * (s.v_new - v0) * (s.v_new - v0));
}

TEST(ServoWalls3D, TheKineticEnergyCountsServoPlanesOnly)
{
  std::vector<Wall3D> walls = box();
  walls[1].velocity = {-0.2, 0, 0};
  walls[0].velocity = {0.3, 0, 0}; // imposed: the loading's, not counted
  EXPECT_DOUBLE_EQ(walls_kinetic_energy(walls), 0.5 * 0.5 * 0.04);
}
