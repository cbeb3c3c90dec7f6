// What the 3D step keeps of a contact between steps and reads per pair: the
// warm start in world coordinates (a contact whose frame turned, or whose
// first tangent switched axis at a tie of contact_frame's rule, gets back the
// same world impulse in its new frame) and the friction of a pair of
// species, or of a species and a 3D wall (its own party).
#include <cmath>
#include <detection/contact_history.h>
#include <detection/friction_table.h>
#include <gtest/gtest.h>

using namespace softpack;

namespace
{
dynamics::Contact3D contact_with_normal(std::array<double, 3> n, int wall = -1)
{
  dynamics::Contact3D c{};
  c.candidate_body = 0;
  c.candidate_node = 7;
  c.antagonist_body = wall >= 0 ? -1 : 1;
  c.wall = wall;
  c.n = n;
  const auto frame = dynamics::contact_frame(n);
  c.t1 = frame[1];
  c.t2 = frame[2];
  return c;
}

std::array<double, 3> world(const dynamics::Contact3D& c, const double* r)
{
  std::array<double, 3> w;
  for (int i = 0; i < 3; ++i)
    w[i] = r[0] * c.n[i] + r[1] * c.t1[i] + r[2] * c.t2[i];
  return w;
}
} // namespace

TEST(ContactMemory3D, WarmStartKeepsTheWorldImpulseAcrossATangentSwitch)
{
  // n at a tie of the rule (|n_y| = |n_z|, the least aligned axis changes
  // on either side of it): t1 turns by 90 degrees between the two steps.
  const double e = 1e-9, k = 1 / std::sqrt(0.81 + 0.18 + 2 * e * e);
  const dynamics::Contact3D before =
      contact_with_normal({0.9 * k, (0.3 - e) * k, (0.3 + e) * k});
  const dynamics::Contact3D after =
      contact_with_normal({0.9 * k, (0.3 + e) * k, (0.3 - e) * k});
  ASSERT_LT(std::abs(before.t1[0] * after.t1[0] + before.t1[1] * after.t1[1] +
                     before.t1[2] * after.t1[2]),
            0.2); // the tangents did switch
  dynamics::ImpulseHistory history;
  const std::vector<double> R = {2.0, 0.3, -0.4};
  history.record(std::vector<dynamics::Contact3D>{before}, R);
  const std::vector<double> start =
      history.warm_start(std::vector<dynamics::Contact3D>{after});
  const std::array<double, 3> w0 = world(before, R.data()),
                              w1 = world(after, start.data());
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(w1[i], w0[i], 1e-12);
  // A new contact (another node) starts from zero
  dynamics::Contact3D other = after;
  other.candidate_node = 8;
  for (double r : history.warm_start(std::vector<dynamics::Contact3D>{other}))
    EXPECT_EQ(r, 0.0);
}

TEST(ContactMemory3D, FrictionOfSpeciesPairsAndOfEachWall)
{
  // Bodies 0 and 1 of species 0 and 1; two walls: wall 0 lubricated
  // (frictionless), wall 1 not set (the default)
  dynamics::FrictionTable table({0, 1}, 2, 2);
  table.set(table.species_party(0), table.species_party(1), 0.4);
  table.set(table.species_party(0), table.wall_party(0), 0.0);
  const dynamics::Contact3D between = contact_with_normal({0, 0, 1});
  EXPECT_EQ(table(between, 0.9), 0.4);
  EXPECT_EQ(table(contact_with_normal({0, 0, 1}, 0), 0.9), 0.0);
  EXPECT_EQ(table(contact_with_normal({0, 0, 1}, 1), 0.9), 0.9);
}
