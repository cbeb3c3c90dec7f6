// 3D node-to-face detection: the nearest point on a triangle in each
// regime, gaps, normals and frames against hand-computed values, the broad
// phase against brute force on random icospheres, invariance under a rigid
// motion, the alert window, walls and the surface checks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <detection/box_grid.h>
#include <detection/detection_3d.h>
#include <detection/mirrored.h>
#include <gtest/gtest.h>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <surface_fixtures.h>

using namespace softpack::dynamics;
using softpack::test::icosphere;
using softpack::test::Mesh;
using softpack::test::octahedron;

namespace
{
using Vec = std::array<double, 3>;
using Tri = std::array<std::int32_t, 3>;

double dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
          a[0] * b[1] - a[1] * b[0]};
}
Vec unit(Vec a)
{
  const double l = std::sqrt(dot(a, a));
  return {a[0] / l, a[1] / l, a[2] / l};
}

/// Bodies made of meshes, each scaled, turned and moved: the surfaces and
/// the coordinates (3 per node, the bodies' nodes one after another)
struct Scene
{
  std::vector<BoundarySurface> surfaces;
  std::vector<double> x;

  void
  add(const Mesh& m, double radius, const Vec& centre,
      const std::array<Vec, 3>& rotation = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      const std::vector<double>& radial = {})
  {
    std::vector<std::int32_t> nodes;
    for (std::size_t i = 0; i < m.points.size(); ++i)
    {
      const double r = radius * (radial.empty() ? 1.0 : radial[i]);
      nodes.push_back(static_cast<std::int32_t>(x.size() / 3));
      for (int d = 0; d < 3; ++d)
        x.push_back(centre[d] + r * dot(rotation[d], m.points[i]));
    }
    surfaces.emplace_back(nodes, m.triangles);
  }
};

/// The rotation of angle `angle` about the unit axis (rows)
std::array<Vec, 3> rotation(Vec axis, double angle)
{
  axis = unit(axis);
  const double c = std::cos(angle), s = std::sin(angle);
  std::array<Vec, 3> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      const Vec e = {double(j == 0), double(j == 1), double(j == 2)};
      const Vec ax = cross(axis, e);
      r[i][j] = c * e[i] + s * ax[i] + (1 - c) * axis[i] * dot(axis, e);
    }
  return r;
}

std::vector<std::int32_t> all_triangles(const BoundarySurface& s)
{
  std::vector<std::int32_t> t(s.triangles().size());
  for (std::size_t i = 0; i < t.size(); ++i)
    t[i] = static_cast<std::int32_t>(i);
  return t;
}

/// The contact of node 0 of body 1 (a one-point probe) with body 0
bool probe(Scene& scene, const Vec& p, const DetectionOptions& options,
           Contact3D& c)
{
  std::copy(p.begin(), p.end(), scene.x.end() - 3 * 4); // the probe's apex
  return node_to_surface(scene.surfaces, scene.x, 1, 0, 0,
                         all_triangles(scene.surfaces[0]), options, c);
}

/// Body 0 the unit octahedron, body 1 a small tetrahedron whose node 0
/// is the probe point
Scene octahedron_and_probe()
{
  Scene s;
  s.add(octahedron(), 1.0, {0, 0, 0});
  Mesh tet;
  tet.points = {{0, 0, 0}, {5, 5, 5}, {5, 6, 5}, {5, 5, 6}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.add(tet, 1.0, {0, 0, 0});
  return s;
}
} // namespace

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

namespace
{
/// A random rotation (a random axis and angle)
std::array<Vec, 3> random_rotation(std::mt19937& gen)
{
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  return rotation({g(gen), g(gen), g(gen)}, angle(gen));
}

/// Radii 1 +- amplitude per point: an irregular closed surface
std::vector<double> bumps(std::size_t n, double amplitude, std::mt19937& gen)
{
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  std::vector<double> r(n);
  for (double& v : r)
    v = 1 + u(gen);
  return r;
}

/// Two level-3 icospheres (R = 1 cm, radii +-1 %, 642 nodes, 1280
/// triangles) overlapping by 0.3 mm, then 3 x 2 x 2 level-2 ones (+-1 %)
/// on a lattice of spacing 2R - 0.2 mm +- 0.2 mm, every sphere turned at
/// random
Scene random_spheres(std::mt19937& gen)
{
  const double R = 0.01;
  Scene s;
  const Mesh fine = icosphere(3), coarse = icosphere(2);
  const Vec axis = unit({1, 0.3, -0.2});
  s.add(fine, R, {0, 0, 0}, random_rotation(gen),
        bumps(fine.points.size(), 0.01, gen));
  s.add(fine, R,
        {(2 * R - 3e-4) * axis[0], (2 * R - 3e-4) * axis[1],
         (2 * R - 3e-4) * axis[2]},
        random_rotation(gen), bumps(fine.points.size(), 0.01, gen));
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4);
  const double L = 2 * R - 2e-4;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k)
        s.add(coarse, R,
              {0.1 + L * i + jitter(gen), L * j + jitter(gen),
               L * k + jitter(gen)},
              random_rotation(gen), bumps(coarse.points.size(), 0.01, gen));
  return s;
}

/// Every node of every body against every triangle of every other body
std::vector<Contact3D> brute_force(const Scene& s,
                                   const DetectionOptions& options)
{
  std::vector<Contact3D> all;
  const int n = static_cast<int>(s.surfaces.size());
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
    {
      std::vector<Contact3D> pair;
      for (const auto& [cand, ant] : {std::pair{a, b}, std::pair{b, a}})
        for (std::int32_t node : s.surfaces[cand].boundary_nodes())
        {
          Contact3D c;
          if (node_to_surface(s.surfaces, s.x, cand, node, ant,
                              all_triangles(s.surfaces[ant]), options, c))
            pair.push_back(c);
        }
      remove_mirrored(pair, 0,
                      [](const Contact3D& c) -> std::int32_t
                      {
                        for (int k = 0; k < 3; ++k)
                          if (c.weights[k] >= 0.75)
                            return c.triangle[k];
                        return -1;
                      });
      all.insert(all.end(), pair.begin(), pair.end());
    }
  return all;
}
} // namespace

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
