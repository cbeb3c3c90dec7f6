// Node-to-segment detection: gaps, frames, both directions, walls, and the
// broad phase.
#include <algorithm>
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <detection/detection.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

namespace
{
bodies::BodySet disks(const std::vector<std::array<double, 3>>& spec,
                      int rings = 4, int rings_of_second = 0)
{
  std::vector<test::Triangulation> parts;
  for (const auto& [x, y, r] : spec)
    parts.push_back(test::disk(
        x, y, r,
        parts.size() == 1 && rings_of_second ? rings_of_second : rings));
  return bodies::BodySet(test::bodies_mesh(parts),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), 1180);
}

std::vector<double> positions(const bodies::BodySet& b)
{
  return {b.reference_coordinates().begin(), b.reference_coordinates().end()};
}
} // namespace

TEST(Detection, TwoTouchingDisksGiveContactsInBothDirections)
{
  const double R = 0.01, gap = 2e-5;
  // 24 and 54 boundary nodes: staggered except on the x axis.
  bodies::BodySet bodies = disks({{0, 0, R}, {2 * R + gap, 0, R}}, 4, 9);
  dynamics::DetectionOptions options;
  options.alert_distance = 1.5e-3; // the neighbours of the axis nodes
  const auto contacts =
      dynamics::detect_contacts(bodies, positions(bodies), {}, options);
  int forward = 0, backward = 0;
  for (const auto& c : contacts)
  {
    (c.candidate_body == 0 ? forward : backward)++;
    EXPECT_LE(c.gap, options.alert_distance);
    EXPECT_NEAR(std::hypot(c.n[0], c.n[1]), 1.0, 1e-14);
    EXPECT_NEAR(c.n[0] * c.t[0] + c.n[1] * c.t[1], 0.0, 1e-14);
    // n points from the antagonist towards the candidate
    EXPECT_GT(c.candidate_body == 0 ? -c.n[0] : c.n[0], 0.9);
  }
  EXPECT_GE(forward, 1);
  EXPECT_GE(backward, 1);
  // The two x-axis nodes face each other: one constraint, one contact.
  int axis = 0;
  for (const auto& c : contacts)
    if (std::abs(c.gap - gap) < 1e-12)
      ++axis;
  EXPECT_EQ(axis, 1);
  // The node on the x axis faces the other disk's node, a vertex: the
  // normal is the bisector of the vertex's segments, the x axis, and the
  // gap is exact.
  double min_gap = 1;
  for (const auto& c : contacts)
    min_gap = std::min(min_gap, c.gap);
  EXPECT_NEAR(min_gap, gap, 1e-12);
}

TEST(Detection, FarDisksHaveNoContactAndWallsSeeTheirNodes)
{
  const double R = 0.01;
  bodies::BodySet bodies = disks({{0, 0, R}, {3 * R, 0, R}});
  std::vector<dynamics::Wall> walls = {
      {"floor", {0, -R - 5e-5}, {0, 1}, {0, 0}}};
  dynamics::DetectionOptions options;
  options.alert_distance = 1e-4;
  const auto contacts =
      dynamics::detect_contacts(bodies, positions(bodies), walls, options);
  ASSERT_EQ(contacts.size(), 2u); // the bottom node of each disk
  for (const auto& c : contacts)
  {
    EXPECT_EQ(c.wall, 0);
    EXPECT_EQ(c.antagonist_body, -1);
    EXPECT_NEAR(c.gap, 5e-5, 1e-12);
  }
}

TEST(Detection, BroadPhaseFindsExactlyTheOverlappingBoxes)
{
  // A 7 x 6 lattice of disks, some touching: compare with all pairs.
  std::vector<std::array<double, 3>> spec;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 6; ++j)
      spec.push_back({0.021 * i + 0.002 * (j % 3), 0.0205 * j,
                      0.01 + 0.0005 * ((i + j) % 2)});
  bodies::BodySet bodies = disks(spec, 2);
  const std::vector<double> x = positions(bodies);
  const double margin = 1e-4;
  const auto pairs = dynamics::near_body_pairs(bodies, x, margin);
  std::vector<std::array<int, 2>> brute;
  for (std::size_t a = 0; a < spec.size(); ++a)
    for (std::size_t b = a + 1; b < spec.size(); ++b)
    {
      // With 12 boundary nodes (every 30 degrees) the polygon's box is the
      // circle's box.
      const auto& A = spec[a];
      const auto& B = spec[b];
      const bool overlap = std::abs(A[0] - B[0]) <= A[2] + B[2] + margin &&
                           std::abs(A[1] - B[1]) <= A[2] + B[2] + margin;
      if (overlap)
        brute.push_back({int(a), int(b)});
    }
  EXPECT_EQ(pairs, brute);
}

TEST(Detection, SharesOfAPartitionOrderedByKeyAreTheWholeList)
{
  // A distributed run detects each rank's share and orders the union by
  // contact_order_key: the result must be the serial list, in its order.
  std::vector<std::array<double, 3>> spec;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      spec.push_back({0.0201 * i, 0.0201 * j, 0.01});
  bodies::BodySet bodies = disks(spec, 3);
  const std::vector<dynamics::Wall> walls = {
      {"floor", {0, -0.01 - 5e-5}, {0, 1}, {0, 0}},
      {"left", {-0.01 - 5e-5, 0}, {1, 0}, {0, 0}}};
  dynamics::DetectionOptions options;
  options.alert_distance = 5e-4;
  const std::vector<double> x = positions(bodies);
  const auto whole = dynamics::detect_contacts(bodies, x, walls, options);
  std::vector<dynamics::Contact> merged;
  const int nb = bodies.num_bodies(), ranks = 3;
  for (int r = 0; r < ranks; ++r)
  {
    std::vector<int> local;
    for (int b = 0; b < nb; ++b)
      if ((b * 7 + 2) % ranks == r) // scattered, not by position
        local.push_back(b);
    bodies::BodySet part = disks(spec, 3);
    part.set_local(local);
    const auto share = dynamics::detect_contacts(part, x, walls, options);
    EXPECT_LT(share.size(), whole.size());
    merged.insert(merged.end(), share.begin(), share.end());
  }
  std::stable_sort(merged.begin(), merged.end(),
                   [nb](const auto& a, const auto& b)
                   {
                     return dynamics::contact_order_key(a, nb) <
                            dynamics::contact_order_key(b, nb);
                   });
  ASSERT_GT(whole.size(), 2u * nb); // pairs and walls both present
  ASSERT_EQ(merged.size(), whole.size());
  for (std::size_t k = 0; k < whole.size(); ++k)
  {
    EXPECT_EQ(merged[k].candidate_body, whole[k].candidate_body) << k;
    EXPECT_EQ(merged[k].candidate_node, whole[k].candidate_node) << k;
    EXPECT_EQ(merged[k].antagonist_body, whole[k].antagonist_body) << k;
    EXPECT_EQ(merged[k].wall, whole[k].wall) << k;
    EXPECT_EQ(merged[k].segment, whole[k].segment) << k;
    EXPECT_EQ(merged[k].gap, whole[k].gap) << k;
  }
}
