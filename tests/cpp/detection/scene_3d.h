#pragma once

// The 3D detection tests' scenes: closed surfaces scaled, turned and
// moved as bodies, a probe node, random icosphere packings, brute force.
#include <algorithm>
#include <cmath>
#include <detection/detection_3d.h>
#include <detection/mirrored.h>
#include <map>
#include <random>
#include <surface_fixtures.h>
#include <vector>

namespace softpack::test::scene3d
{
using namespace softpack::dynamics;
using softpack::test::icosphere;
using softpack::test::Mesh;
using softpack::test::octahedron;

using softpack::test::surface_detail::cross;
using softpack::test::surface_detail::dot;
using softpack::test::surface_detail::unit;
using softpack::test::surface_detail::Vec;
using Tri = std::array<std::int32_t, 3>;

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
inline std::array<Vec, 3> rotation(Vec axis, double angle)
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

inline std::vector<std::int32_t> all_triangles(const BoundarySurface& s)
{
  std::vector<std::int32_t> t(s.triangles().size());
  for (std::size_t i = 0; i < t.size(); ++i)
    t[i] = static_cast<std::int32_t>(i);
  return t;
}

/// The contact of node 0 of body 1 (a one-point probe) with body 0
inline bool probe(Scene& scene, const Vec& p, const DetectionOptions& options,
                  Contact3D& c)
{
  std::copy(p.begin(), p.end(), scene.x.end() - 3 * 4); // the probe's apex
  return node_to_surface(scene.surfaces, scene.x, 1, 0, 0,
                         all_triangles(scene.surfaces[0]), options, c);
}

/// Body 0 the unit octahedron, body 1 a small tetrahedron whose node 0
/// is the probe point
inline Scene octahedron_and_probe()
{
  Scene s;
  s.add(octahedron(), 1.0, {0, 0, 0});
  Mesh tet;
  tet.points = {{0, 0, 0}, {5, 5, 5}, {5, 6, 5}, {5, 5, 6}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.add(tet, 1.0, {0, 0, 0});
  return s;
}

/// A random rotation (a random axis and angle)
inline std::array<Vec, 3> random_rotation(std::mt19937& gen)
{
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  return rotation({g(gen), g(gen), g(gen)}, angle(gen));
}

/// Radii 1 +- amplitude per point: an irregular closed surface
inline std::vector<double> bumps(std::size_t n, double amplitude,
                                 std::mt19937& gen)
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
inline Scene random_spheres(std::mt19937& gen)
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
inline std::vector<Contact3D> brute_force(const Scene& s,
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
} // namespace softpack::test::scene3d
