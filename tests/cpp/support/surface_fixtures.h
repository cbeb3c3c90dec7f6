#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

/// Closed triangulated surfaces built in memory, for the 3D detection's
/// tests and benchmark (no gmsh needed).
namespace softpack::test
{
namespace surface_detail
{
using Vec = std::array<double, 3>;
inline double dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec cross(const Vec& a, const Vec& b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
          a[0] * b[1] - a[1] * b[0]};
}
inline Vec unit(Vec a)
{
  const double l = std::sqrt(dot(a, a));
  return {a[0] / l, a[1] / l, a[2] / l};
}
} // namespace surface_detail

/// A closed triangulated surface: unit-sphere points and outward triangles
struct Mesh
{
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
};

/// The regular octahedron, vertices +-e_i (0: +x, 1: -x, 2: +y, 3: -y,
/// 4: +z, 5: -z)
inline Mesh octahedron()
{
  using namespace surface_detail;
  using Tri = std::array<std::int32_t, 3>;
  Mesh m;
  m.points = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
              {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (int i : {0, 1})
    for (int j : {2, 3})
      for (int k : {4, 5})
      {
        Tri t = {i, j, k};
        const Vec n = cross(
            {m.points[j][0] - m.points[i][0], m.points[j][1] - m.points[i][1],
             m.points[j][2] - m.points[i][2]},
            {m.points[k][0] - m.points[i][0], m.points[k][1] - m.points[i][1],
             m.points[k][2] - m.points[i][2]});
        const Vec centre = {(m.points[i][0] + m.points[j][0] + m.points[k][0]),
                            (m.points[i][1] + m.points[j][1] + m.points[k][1]),
                            (m.points[i][2] + m.points[j][2] + m.points[k][2])};
        if (dot(n, centre) < 0)
          std::swap(t[1], t[2]);
        m.triangles.push_back(t);
      }
  return m;
}

/// The icosahedron's faces split `level` times, points on the unit sphere
/// (level 2: 162 points, 320 triangles; level 3: 642, 1280)
inline Mesh icosphere(int level)
{
  using namespace surface_detail;
  using Tri = std::array<std::int32_t, 3>;
  const double f = (1 + std::sqrt(5.0)) / 2;
  Mesh m;
  for (double a : {-1.0, 1.0})
    for (double b : {-f, f})
      m.points.insert(m.points.end(), {{a, b, 0}, {0, a, b}, {b, 0, a}});
  // Faces: the triples of points at mutual distance 2, turned outward
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
      {
        auto d2 = [&](int p, int q)
        {
          Vec d = {m.points[p][0] - m.points[q][0],
                   m.points[p][1] - m.points[q][1],
                   m.points[p][2] - m.points[q][2]};
          return dot(d, d);
        };
        if (std::abs(d2(i, j) - 4) > 1e-9 || std::abs(d2(j, k) - 4) > 1e-9 ||
            std::abs(d2(i, k) - 4) > 1e-9)
          continue;
        const Vec& a = m.points[i];
        const Vec& b = m.points[j];
        const Vec& c = m.points[k];
        const Vec n = cross({b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                            {c[0] - a[0], c[1] - a[1], c[2] - a[2]});
        m.triangles.push_back(dot(n, a) > 0 ? Tri{i, j, k} : Tri{i, k, j});
      }
  for (Vec& p : m.points)
    p = unit(p);
  for (int l = 0; l < level; ++l)
  {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b)
    {
      const auto key = std::minmax(a, b);
      auto [it, added] = middle.emplace(key, int(m.points.size()));
      if (added)
        m.points.push_back(unit({m.points[a][0] + m.points[b][0],
                                 m.points[a][1] + m.points[b][1],
                                 m.points[a][2] + m.points[b][2]}));
      return it->second;
    };
    std::vector<Tri> split;
    for (const auto& [a, b, c] : m.triangles)
    {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      split.insert(split.end(),
                   {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
    }
    m.triangles = split;
  }
  return m;
}

} // namespace softpack::test
