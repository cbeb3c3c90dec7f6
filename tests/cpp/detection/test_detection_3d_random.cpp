// 3D node-to-face detection on random icosphere packings: the broad phase
// against brute force, invariance under a rigid motion, and the sign of
// the gap against inside/outside by ray casting.
#include "scene_3d.h"
#include <cmath>
#include <cstdio>
#include <detection/box_grid.h>
#include <detection/detection_3d.h>
#include <gtest/gtest.h>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

using namespace softpack::test::scene3d;

TEST(Detection3D, BroadPhaseGivesTheBruteForceContacts)
{
  std::mt19937 gen(7);
  const Scene s = random_spheres(gen);
  DetectionOptions options;
  options.alert_distance = 1e-3; // a wide window: many contacts
  options.max_penetration = 1e-3;
  const auto contacts = detect_contacts_3d(s.surfaces, s.x, {}, options);
  const auto brute = brute_force(s, options);
  ASSERT_EQ(contacts.size(), brute.size());
  std::map<Feature, int> features;
  std::set<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < brute.size(); ++i)
  {
    const Contact3D &c = contacts[i], &b = brute[i];
    EXPECT_EQ(c.candidate_body, b.candidate_body) << i;
    EXPECT_EQ(c.candidate_node, b.candidate_node) << i;
    EXPECT_EQ(c.antagonist_body, b.antagonist_body) << i;
    EXPECT_EQ(c.triangle, b.triangle) << i;
    EXPECT_EQ(c.weights, b.weights) << i;
    EXPECT_EQ(c.gap, b.gap) << i;
    EXPECT_EQ(c.n, b.n) << i;
    EXPECT_LE(c.gap, options.alert_distance);
    EXPECT_GE(c.gap, -options.max_penetration);
    ++features[c.feature];
    pairs.insert(std::minmax(c.candidate_body, c.antagonist_body));
  }
  // The fine pair and the lattice's neighbours touch: many contacts, in
  // both directions, most on faces
  std::printf("%zu contacts over %zu pairs: %d face, %d edge, %d vertex\n",
              contacts.size(), pairs.size(), features[Feature::face],
              features[Feature::edge], features[Feature::vertex]);
  EXPECT_GT(contacts.size(), 100u);
  EXPECT_GT(features[Feature::face], features[Feature::edge]);
  EXPECT_GT(pairs.size(), 10u);
}

TEST(Detection3D, GapsAreInvariantUnderARigidMotion)
{
  std::mt19937 gen(9);
  Scene s = random_spheres(gen);
  DetectionOptions options;
  options.alert_distance = 1e-3;
  options.max_penetration = 1e-3;
  const auto before = detect_contacts_3d(s.surfaces, s.x, {}, options);
  const auto Q = random_rotation(gen);
  const Vec shift = {0.3, -1.2, 0.7};
  for (std::size_t i = 0; i < s.x.size(); i += 3)
  {
    const Vec p = {s.x[i], s.x[i + 1], s.x[i + 2]};
    for (int d = 0; d < 3; ++d)
      s.x[i + d] = dot(Q[d], p) + shift[d];
  }
  const auto after = detect_contacts_3d(s.surfaces, s.x, {}, options);
  ASSERT_EQ(after.size(), before.size());
  ASSERT_GT(before.size(), 100u);
  for (std::size_t i = 0; i < before.size(); ++i)
  {
    const Contact3D &a = before[i], &b = after[i];
    EXPECT_EQ(a.candidate_node, b.candidate_node) << i;
    EXPECT_EQ(a.antagonist_body, b.antagonist_body) << i;
    EXPECT_EQ(a.feature, b.feature) << i;
    EXPECT_NEAR(a.gap, b.gap, 1e-14) << i; // 1e-12 of the radius
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(dot(Q[d], a.n), b.n[d], 1e-11) << i;
  }
}

TEST(Detection3D, GapSignTellsInsideFromOutsideNearEdgesAndVertices)
{
  // Points near a bumpy level-2 icosphere (radii +-5 %: concave edges and
  // vertices too), displaced from its surface in random directions:
  // inside (by a ray from the centre, independent of the detection) iff
  // the gap is negative, whatever the nearest feature.
  std::mt19937 gen(13);
  const Mesh m = icosphere(2);
  Scene s;
  const double R = 0.01;
  s.add(m, R, {0, 0, 0}, random_rotation(gen),
        bumps(m.points.size(), 0.05, gen));
  Mesh tet;
  tet.points = {{0, 0, 0}, {5, 5, 5}, {5, 6, 5}, {5, 5, 6}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.add(tet, 1.0, {0, 0, 0});
  DetectionOptions options;
  options.alert_distance = 2e-3;
  options.max_penetration = 2e-3;
  auto point = [&](std::int32_t t, int i)
  {
    const std::int32_t g =
        s.surfaces[0].nodes()[s.surfaces[0].triangles()[t][i]];
    return Vec{s.x[3 * g], s.x[3 * g + 1], s.x[3 * g + 2]};
  };
  // Distance from the centre to the surface along the unit direction d
  auto surface_distance = [&](const Vec& d)
  {
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
    {
      const Vec a = point(t, 0), b = point(t, 1), c = point(t, 2);
      // d s = a + u (b - a) + v (c - a), by Cramer's rule
      const Vec e1 = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const Vec e2 = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const Vec na = {-a[0], -a[1], -a[2]};
      const double det = dot(d, cross(e1, e2));
      const double dist = dot(a, cross(e1, e2)) / det;
      const double u = dot(d, cross(na, e2)) / det;
      const double v = dot(d, cross(e1, na)) / det;
      if (dist > 0 && u >= 0 && v >= 0 && u + v <= 1)
        return dist;
    }
    return -1.0;
  };
  std::uniform_int_distribution<int> pick(0, int(m.triangles.size()) - 1);
  std::uniform_real_distribution<double> u01(0, 1), step(0, 1.5e-3);
  std::normal_distribution<double> g;
  std::map<Feature, int> features;
  for (int trial = 0; trial < 3000; ++trial)
  {
    // From a point of a face, of an edge or a vertex in turn
    const int t = pick(gen);
    double w1 = u01(gen), w2 = u01(gen);
    if (w1 + w2 > 1)
      w1 = 1 - w1, w2 = 1 - w2;
    if (trial % 3 == 1)
      w2 = 0;
    else if (trial % 3 == 2)
      w1 = w2 = 0;
    const Vec a = point(t, 0), b = point(t, 1), c = point(t, 2);
    Vec p, d = unit({g(gen), g(gen), g(gen)});
    for (int k = 0; k < 3; ++k)
      p[k] = (1 - w1 - w2) * a[k] + w1 * b[k] + w2 * c[k];
    if (trial % 3 != 0) // near the radial direction, in or out: the
    {                   // edge's and vertex's regions are narrow cones
      const Vec radial = unit(p);
      const double side = u01(gen) < 0.5 ? -1 : 1;
      d = unit({side * radial[0] + 0.15 * d[0], side * radial[1] + 0.15 * d[1],
                side * radial[2] + 0.15 * d[2]});
    }
    const double h = step(gen);
    for (int k = 0; k < 3; ++k)
      p[k] += h * d[k];
    const double rho = std::sqrt(dot(p, p)),
                 surface = surface_distance(unit(p));
    ASSERT_GT(surface, 0);
    Contact3D contact;
    if (!probe(s, p, options, contact) || std::abs(rho - surface) < 1e-12)
      continue;
    ++features[contact.feature];
    EXPECT_EQ(contact.gap < 0, rho < surface) << trial << " " << contact.gap;
  }
  std::printf("%d face, %d edge, %d vertex\n", features[Feature::face],
              features[Feature::edge], features[Feature::vertex]);
  EXPECT_GT(features[Feature::face], 500);
  EXPECT_GT(features[Feature::edge], 300);
  EXPECT_GT(features[Feature::vertex], 50);
}
