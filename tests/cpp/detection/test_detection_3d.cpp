// 3D node-to-face detection: the nearest point on a triangle in each
// regime, gaps, normals and frames against hand-computed values, the alert
// window, walls, the surface checks and the generic broad phase.
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

TEST(NearestOnTriangle, EachRegimeAgainstHandValues)
{
  const Vec a = {0, 0, 0}, b = {2, 0, 0}, c = {0, 2, 0};
  struct Case
  {
    Vec p;
    Feature feature;
    int k;
    Vec weights;
    double distance2;
  };
  const std::vector<Case> cases = {
      {{0.5, 0.5, 1}, Feature::face, 0, {0.5, 0.25, 0.25}, 1},
      {{1, -1, 0.5}, Feature::edge, 0, {0.5, 0.5, 0}, 1.25},
      {{2, 2, 1}, Feature::edge, 1, {0, 0.5, 0.5}, 3},
      {{-1, 1.5, 0}, Feature::edge, 2, {0.25, 0, 0.75}, 1},
      {{-1, -1, 3}, Feature::vertex, 0, {1, 0, 0}, 11},
      {{3, -1, 0}, Feature::vertex, 1, {0, 1, 0}, 2},
      {{-0.5, 3, 0}, Feature::vertex, 2, {0, 0, 1}, 1.25}};
  for (const Case& k : cases)
  {
    const TrianglePoint q =
        nearest_on_triangle(k.p.data(), a.data(), b.data(), c.data());
    EXPECT_EQ(q.feature, k.feature);
    EXPECT_EQ(q.k, k.k);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(q.weights[i], k.weights[i], 1e-15);
    EXPECT_NEAR(q.distance2, k.distance2, 1e-14);
  }
}

TEST(NearestOnTriangle, RandomPointsAgainstTheStationaryPoints)
{
  // The independent reference: the least distance among the vertices, the
  // clamped projections on the three edge lines and the projection on the
  // plane when its barycentric coordinates are all >= 0.
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 2000; ++trial)
  {
    std::array<Vec, 3> v;
    Vec p;
    for (auto& w : v)
      w = {u(gen), u(gen), u(gen)};
    p = {2 * u(gen), 2 * u(gen), 2 * u(gen)};
    auto dist2 = [&](const Vec& q)
    {
      return dot({p[0] - q[0], p[1] - q[1], p[2] - q[2]},
                 {p[0] - q[0], p[1] - q[1], p[2] - q[2]});
    };
    double best = 1e300;
    for (int i = 0; i < 3; ++i)
    {
      const Vec& s = v[i];
      const Vec& e = v[(i + 1) % 3];
      const Vec d = {e[0] - s[0], e[1] - s[1], e[2] - s[2]};
      const double t = std::clamp(
          dot({p[0] - s[0], p[1] - s[1], p[2] - s[2]}, d) / dot(d, d), 0.0,
          1.0);
      best = std::min(
          best, dist2({s[0] + t * d[0], s[1] + t * d[1], s[2] + t * d[2]}));
    }
    const Vec e1 = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
    const Vec e2 = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
    const Vec r = {p[0] - v[0][0], p[1] - v[0][1], p[2] - v[0][2]};
    // Normal equations of min |e1 s + e2 t - r|
    const double a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2);
    const double det = a11 * a22 - a12 * a12;
    const double s = (a22 * dot(e1, r) - a12 * dot(e2, r)) / det;
    const double t = (a11 * dot(e2, r) - a12 * dot(e1, r)) / det;
    if (s >= 0 && t >= 0 && s + t <= 1)
      best = std::min(best, dist2({v[0][0] + s * e1[0] + t * e2[0],
                                   v[0][1] + s * e1[1] + t * e2[1],
                                   v[0][2] + s * e1[2] + t * e2[2]}));
    const TrianglePoint q =
        nearest_on_triangle(p.data(), v[0].data(), v[1].data(), v[2].data());
    EXPECT_NEAR(q.distance2, best, 1e-12 * (1 + best)) << trial;
    EXPECT_NEAR(q.weights[0] + q.weights[1] + q.weights[2], 1.0, 1e-14);
    for (double w : q.weights)
      EXPECT_GE(w, 0.0);
  }
}

TEST(Detection3D, FrameIsOrthonormalRightHandedAndDeterministic)
{
  // n = e_z: the least aligned axis is e_x (first of equals),
  // t1 = e_x x e_z = -e_y, t2 = n x t1 = e_x
  const auto f = contact_frame({0, 0, 1});
  EXPECT_EQ(f[1], (Vec{0, -1, 0}));
  EXPECT_EQ(f[2], (Vec{1, 0, 0}));
  std::mt19937 gen(5);
  std::normal_distribution<double> g;
  for (int i = 0; i < 1000; ++i)
  {
    const Vec n = unit({g(gen), g(gen), g(gen)});
    const auto [n0, t1, t2] = contact_frame(n);
    EXPECT_EQ(n0, n);
    EXPECT_NEAR(dot(t1, t1), 1, 1e-15);
    EXPECT_NEAR(dot(t2, t2), 1, 1e-15);
    EXPECT_NEAR(dot(n, t1), 0, 1e-15);
    EXPECT_NEAR(dot(n, t2), 0, 1e-15);
    EXPECT_NEAR(dot(t1, t2), 0, 1e-15);
    const Vec c = cross(t1, t2); // right-handed: t1 x t2 = n
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(c[d], n[d], 1e-15);
    EXPECT_EQ(contact_frame(n)[1], t1);
  }
}

TEST(Detection3D, NodeOnOctahedronFaceEdgeAndVertex)
{
  // Unit octahedron: face (+x, +y, +z) has the normal (1, 1, 1)/sqrt 3; the
  // edge (+x, +y) the bisector (1, 1, 0)/sqrt 2 of its faces' normals; the
  // vertex +x, with four equal angles, the normal e_x.
  Scene s = octahedron_and_probe();
  DetectionOptions options;
  options.alert_distance = 0.1;
  options.max_penetration = 0.05;
  const double r3 = 1 / std::sqrt(3.0), r2 = 1 / std::sqrt(2.0);
  const Vec nf = {r3, r3, r3}, ne = {r2, r2, 0};
  // On the face, outside and inside; the nearest of the faces a point
  // inside projects onto; on the edge along the bisector and off it; on
  // the vertex along its normal and off it.
  const Vec off = unit({1, 1, 0.5}), voff = unit({1, 0.2, 0.1});
  struct Case
  {
    Vec p;
    Feature feature;
    Vec n;
    double gap;
    std::map<int, double> weights; // octahedron node -> weight
  };
  const double third = 1.0 / 3;
  const std::vector<Case> cases = {
      {{third + 0.04 * r3, third + 0.04 * r3, third + 0.04 * r3},
       Feature::face,
       nf,
       0.04,
       {{0, third}, {2, third}, {4, third}}},
      {{third - 0.03 * r3, third - 0.03 * r3, third - 0.03 * r3},
       Feature::face,
       nf,
       -0.03,
       {{0, third}, {2, third}, {4, third}}},
      {{0.45, 0.4, 0.1},
       Feature::face,
       nf,
       -0.05 * r3,
       {{0, 0.45 + 0.05 / 3}, {2, 0.4 + 0.05 / 3}, {4, 0.1 + 0.05 / 3}}},
      {{0.5 + 0.04 * r2, 0.5 + 0.04 * r2, 0},
       Feature::edge,
       ne,
       0.04,
       {{0, 0.5}, {2, 0.5}}},
      {{0.5 + 0.04 * off[0], 0.5 + 0.04 * off[1], 0.04 * off[2]},
       Feature::edge,
       ne,
       0.04 * dot(off, ne),
       {{0, 0.5}, {2, 0.5}}},
      {{1.04, 0, 0}, Feature::vertex, {1, 0, 0}, 0.04, {{0, 1}}},
      {{1 + 0.04 * voff[0], 0.04 * voff[1], 0.04 * voff[2]},
       Feature::vertex,
       {1, 0, 0},
       0.04 * voff[0],
       {{0, 1}}}};
  for (std::size_t i = 0; i < cases.size(); ++i)
  {
    const Case& k = cases[i];
    Contact3D c;
    ASSERT_TRUE(probe(s, k.p, options, c)) << i;
    EXPECT_EQ(c.candidate_body, 1);
    EXPECT_EQ(c.candidate_node, 0);
    EXPECT_EQ(c.antagonist_body, 0);
    EXPECT_EQ(c.wall, -1);
    EXPECT_EQ(c.feature, k.feature) << i;
    EXPECT_NEAR(c.gap, k.gap, 1e-15) << i;
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(c.n[d], k.n[d], 1e-15) << i;
    std::map<int, double> w;
    for (int j = 0; j < 3; ++j)
      if (c.weights[j] != 0)
        w[c.triangle[j]] = c.weights[j];
    ASSERT_EQ(w.size(), k.weights.size()) << i;
    for (const auto& [node, weight] : k.weights)
      EXPECT_NEAR(w[node], weight, 1e-15) << i;
    const auto frame = contact_frame(c.n);
    EXPECT_EQ(c.t1, frame[1]);
    EXPECT_EQ(c.t2, frame[2]);
  }
}

TEST(Detection3D, AlertDistanceAndMaxPenetrationBoundTheGap)
{
  Scene s = octahedron_and_probe();
  DetectionOptions options;
  options.alert_distance = 0.1;
  options.max_penetration = 0.05;
  const double r3 = 1 / std::sqrt(3.0), third = 1.0 / 3;
  Contact3D c;
  for (const auto& [g, kept] : std::vector<std::pair<double, bool>>{
           {0.0999, true}, {0.1001, false}, {-0.0499, true}, {-0.0501, false}})
  {
    const Vec p = {third + g * r3, third + g * r3, third + g * r3};
    EXPECT_EQ(probe(s, p, options, c), kept) << g;
    if (kept)
      EXPECT_NEAR(c.gap, g, 1e-15);
  }
  // In the vertex +x's region, 0.101 from it (beyond the search distance
  // max(alert, max_penetration) = 0.1) though 0.075 along its normal: no
  // contact; 0.099 from it: a contact of gap 0.099 x 0.743
  const Vec d = unit({1, 0.9, 0});
  EXPECT_FALSE(probe(s, {1 + 0.101 * d[0], 0.101 * d[1], 0}, options, c));
  ASSERT_TRUE(probe(s, {1 + 0.099 * d[0], 0.099 * d[1], 0}, options, c));
  EXPECT_EQ(c.feature, Feature::vertex);
  EXPECT_NEAR(c.gap, 0.099 * d[0], 1e-15);
}

TEST(Detection3D, WallsSeeTheNodesWithinTheWindow)
{
  Scene s;
  s.add(octahedron(), 1.0, {0, 0, 0});
  DetectionOptions options;
  options.alert_distance = 0.1;
  options.max_penetration = 0.05;
  const std::vector<PlaneWall> walls = {{{0, 0, -1.03}, {0, 0, 1}},
                                        {{0.97, 5, 5}, {-1, 0, 0}}};
  const auto contacts = detect_contacts_3d(s.surfaces, s.x, walls, options);
  ASSERT_EQ(contacts.size(), 2u);
  EXPECT_EQ(contacts[0].wall, 0);
  EXPECT_EQ(contacts[0].candidate_node, 5); // -z
  EXPECT_NEAR(contacts[0].gap, 0.03, 1e-15);
  EXPECT_EQ(contacts[1].wall, 1);
  EXPECT_EQ(contacts[1].candidate_node, 0); // +x, 0.03 inside the wall
  EXPECT_NEAR(contacts[1].gap, -0.03, 1e-15);
  for (const auto& c : contacts)
  {
    EXPECT_EQ(c.antagonist_body, -1);
    EXPECT_EQ(c.n, walls[c.wall].normal);
    EXPECT_EQ(c.t1, contact_frame(c.n)[1]);
  }
  const std::vector<PlaneWall> long_normal = {{{0, 0, -1.03}, {0, 0, 1.1}}};
  EXPECT_THROW(detect_contacts_3d(s.surfaces, s.x, long_normal, options),
               std::invalid_argument);
}

TEST(Detection3D, SurfaceMustBeClosedAndOriented)
{
  Mesh m = octahedron();
  std::vector<std::int32_t> nodes = {0, 1, 2, 3, 4, 5};
  EXPECT_NO_THROW(BoundarySurface(nodes, m.triangles));
  auto open = m.triangles;
  open.pop_back();
  EXPECT_THROW(BoundarySurface(nodes, open), std::invalid_argument);
  auto flipped = m.triangles;
  std::swap(flipped[3][1], flipped[3][2]);
  EXPECT_THROW(BoundarySurface(nodes, flipped), std::invalid_argument);
  auto wrong = m.triangles;
  wrong[0][0] = 6;
  EXPECT_THROW(BoundarySurface(nodes, wrong), std::invalid_argument);
}

TEST(BroadPhase, OverlappingPairsAreThoseOfAllPairsIn2DAnd3D)
{
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> pos(0, 1), size(0.01, 0.08);
  auto check = [&]<int D>(std::integral_constant<int, D>)
  {
    std::vector<Box<D>> boxes(600);
    for (auto& b : boxes)
      for (int d = 0; d < D; ++d)
      {
        b.lo[d] = pos(gen);
        b.hi[d] = b.lo[d] + size(gen);
      }
    const double margin = 0.005;
    std::vector<std::array<int, 2>> brute;
    for (int a = 0; a < int(boxes.size()); ++a)
      for (int b = a + 1; b < int(boxes.size()); ++b)
        if (boxes[a].overlaps(boxes[b], margin))
          brute.push_back({a, b});
    EXPECT_GT(brute.size(), 100u);
    EXPECT_EQ(overlapping_pairs<D>(boxes, margin), brute);
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

TEST(Detection3D, CollapsedTriangleIsReportedNotSkipped)
{
  // A tetrahedron collapsed onto a line (every face of zero area) under
  // the probe: no normal, so an error naming the bodies
  Scene s;
  Mesh flat;
  flat.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  flat.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.add(flat, 1.0, {0, 0, 0});
  Mesh tet;
  tet.points = {{1.5, 0, 0.01}, {1.5, 0, 1}, {1.6, 0, 1}, {1.5, 0.1, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.add(tet, 1.0, {0, 0, 0});
  DetectionOptions options;
  options.alert_distance = 0.05;
  EXPECT_THROW(detect_contacts_3d(s.surfaces, s.x, {}, options),
               std::runtime_error);
}
