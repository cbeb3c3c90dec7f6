#include "detection_3d.h"
#include "box_grid.h"
#include "contact_order.h"
#include "mirrored.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace softpack::dynamics
{
namespace
{
using Vec = std::array<double, 3>;

Vec sub(const double* a, const double* b)
{
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
          a[0] * b[1] - a[1] * b[0]};
}
Vec normalised(const Vec& a)
{
  const double len = std::sqrt(dot(a, a));
  return {a[0] / len, a[1] / len, a[2] / len};
}

std::string triangle_name(std::size_t t)
{
  return "boundary triangle " + std::to_string(t);
}
} // namespace

BoundarySurface::BoundarySurface(
    std::vector<std::int32_t> nodes,
    std::vector<std::array<std::int32_t, 3>> triangles)
    : _nodes(std::move(nodes)), _triangles(std::move(triangles))
{
  const auto n = static_cast<std::int32_t>(_nodes.size());
  // Each directed edge (a, b) once: its triangle and edge number
  std::unordered_map<std::int64_t, std::array<std::int32_t, 2>> edges;
  auto key = [](std::int32_t a, std::int32_t b)
  { return (std::int64_t(a) << 32) | std::uint32_t(b); };
  _around_offsets.assign(n + 1, 0);
  for (std::size_t t = 0; t < _triangles.size(); ++t)
  {
    const auto& v = _triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      if (v[k] < 0 || v[k] >= n)
        throw std::invalid_argument(triangle_name(t) + " names node " +
                                    std::to_string(v[k]) + ", not in [0, " +
                                    std::to_string(n) + ")");
      if (v[k] == v[(k + 1) % 3])
        throw std::invalid_argument(triangle_name(t) + " repeats node " +
                                    std::to_string(v[k]));
      if (!edges
               .emplace(key(v[k], v[(k + 1) % 3]),
                        std::array{std::int32_t(t), std::int32_t(k)})
               .second)
        throw std::invalid_argument(
            triangle_name(t) + ": edge " + std::to_string(v[k]) + " -> " +
            std::to_string(v[(k + 1) % 3]) +
            " is in two triangles the same way (not a closed surface "
            "oriented outward)");
      ++_around_offsets[v[k] + 1];
    }
  }
  _neighbours.resize(_triangles.size());
  for (std::size_t t = 0; t < _triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
    {
      const auto& v = _triangles[t];
      auto it = edges.find(key(v[(k + 1) % 3], v[k]));
      if (it == edges.end())
        throw std::invalid_argument(
            triangle_name(t) + ": edge " + std::to_string(v[k]) + " -> " +
            std::to_string(v[(k + 1) % 3]) +
            " has no triangle on its other side the other way (the surface "
            "is not closed or not oriented consistently)");
      _neighbours[t][k] = it->second[0];
    }
  for (std::int32_t i = 0; i < n; ++i)
    _around_offsets[i + 1] += _around_offsets[i];
  _around.resize(_around_offsets[n]);
  std::vector<std::int32_t> fill(_around_offsets.begin(),
                                 _around_offsets.end() - 1);
  for (std::size_t t = 0; t < _triangles.size(); ++t)
    for (std::int32_t v : _triangles[t])
      _around[fill[v]++] = static_cast<std::int32_t>(t);
  for (std::int32_t i = 0; i < n; ++i)
    if (_around_offsets[i + 1] > _around_offsets[i])
      _boundary_nodes.push_back(i);
}

TrianglePoint nearest_on_triangle(const double* p, const double* a,
                                  const double* b, const double* c)
{
  // The Voronoi regions of the vertices, edges and face, tested in turn
  // with the dot products of the edges and the vectors to p (Ericson,
  // Real-Time Collision Detection, 2005, sec. 5.1.5)
  const Vec ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  TrianglePoint r{{1, 0, 0}, Feature::vertex, 0, 0};
  const Vec bp = sub(p, b), cp = sub(p, c);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6,
               va = d3 * d6 - d5 * d4;
  if (d1 <= 0 && d2 <= 0)
    r = {{1, 0, 0}, Feature::vertex, 0, 0};
  else if (d3 >= 0 && d4 <= d3)
    r = {{0, 1, 0}, Feature::vertex, 1, 0};
  else if (d6 >= 0 && d5 <= d6)
    r = {{0, 0, 1}, Feature::vertex, 2, 0};
  else if (vc <= 0 && d1 >= 0 && d3 <= 0)
  {
    const double s = d1 / (d1 - d3);
    r = {{1 - s, s, 0}, Feature::edge, 0, 0};
  }
  else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
  {
    const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    r = {{0, 1 - s, s}, Feature::edge, 1, 0};
  }
  else if (vb <= 0 && d2 >= 0 && d6 <= 0)
  {
    const double s = d2 / (d2 - d6);
    r = {{1 - s, 0, s}, Feature::edge, 2, 0};
  }
  else
  {
    const double sum = va + vb + vc;
    const double v = vb / sum, w = vc / sum;
    r = {{1 - v - w, v, w}, Feature::face, 0, 0};
  }
  Vec d;
  for (int i = 0; i < 3; ++i)
    d[i] = p[i] -
           (r.weights[0] * a[i] + r.weights[1] * b[i] + r.weights[2] * c[i]);
  r.distance2 = dot(d, d);
  return r;
}

std::array<std::array<double, 3>, 3>
contact_frame(const std::array<double, 3>& n)
{
  int e = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) < std::abs(n[e]))
      e = k;
  Vec axis = {0, 0, 0};
  axis[e] = 1;
  const Vec t1 = normalised(cross(axis, n));
  return {n, t1, cross(n, t1)};
}

namespace
{
/// Outward unit normal of triangle t
Vec face_normal(const BoundarySurface& s, std::span<const double> x,
                std::int32_t t)
{
  const auto& v = s.triangles()[t];
  const double* a = &x[3 * std::size_t(s.nodes()[v[0]])];
  const double* b = &x[3 * std::size_t(s.nodes()[v[1]])];
  const double* c = &x[3 * std::size_t(s.nodes()[v[2]])];
  return normalised(cross(sub(b, a), sub(c, a)));
}

/// The normal of a feature: the face's, the sum of the two faces' at an
/// edge, the angle-weighted sum of the faces' around a vertex (with these
/// the sign of (p - q) . n tells inside from outside)
Vec feature_normal(const BoundarySurface& s, std::span<const double> x,
                   std::int32_t t, Feature feature, int k)
{
  if (feature == Feature::face)
    return face_normal(s, x, t);
  if (feature == Feature::edge)
  {
    const Vec n0 = face_normal(s, x, t),
              n1 = face_normal(s, x, s.neighbour(t, k));
    return normalised({n0[0] + n1[0], n0[1] + n1[1], n0[2] + n1[2]});
  }
  const std::int32_t v = s.triangles()[t][k];
  const double* pv = &x[3 * std::size_t(s.nodes()[v])];
  Vec sum = {0, 0, 0};
  for (std::int32_t f : s.triangles_around(v))
  {
    const auto& w = s.triangles()[f];
    const int i = w[0] == v ? 0 : (w[1] == v ? 1 : 2);
    const Vec e1 = sub(&x[3 * std::size_t(s.nodes()[w[(i + 1) % 3]])], pv);
    const Vec e2 = sub(&x[3 * std::size_t(s.nodes()[w[(i + 2) % 3]])], pv);
    const double angle =
        std::atan2(std::sqrt(dot(cross(e1, e2), cross(e1, e2))), dot(e1, e2));
    const Vec nf = face_normal(s, x, f);
    for (int d = 0; d < 3; ++d)
      sum[d] += angle * nf[d];
  }
  return normalised(sum);
}

double search_distance(const DetectionOptions& options)
{
  return std::max(options.alert_distance, options.max_penetration);
}
} // namespace

bool node_to_surface(std::span<const BoundarySurface> surfaces,
                     std::span<const double> x, int cand, std::int32_t node,
                     int ant, std::span<const std::int32_t> candidates,
                     const DetectionOptions& options, Contact3D& contact)
{
  const BoundarySurface& s = surfaces[ant];
  const double* p = &x[3 * std::size_t(surfaces[cand].nodes()[node])];
  std::int32_t best = -1;
  TrianglePoint nearest{};
  for (std::int32_t t : candidates)
  {
    const auto& v = s.triangles()[t];
    const TrianglePoint q =
        nearest_on_triangle(p, &x[3 * std::size_t(s.nodes()[v[0]])],
                            &x[3 * std::size_t(s.nodes()[v[1]])],
                            &x[3 * std::size_t(s.nodes()[v[2]])]);
    if (best < 0 || q.distance2 < nearest.distance2 ||
        (q.distance2 == nearest.distance2 && t < best))
    {
      best = t;
      nearest = q;
    }
  }
  const double r = search_distance(options);
  if (best < 0 || nearest.distance2 > r * r)
    return false;
  const auto& v = s.triangles()[best];
  const Vec n = feature_normal(s, x, best, nearest.feature, nearest.k);
  Vec d;
  for (int i = 0; i < 3; ++i)
  {
    double q = 0;
    for (int j = 0; j < 3; ++j)
      q += nearest.weights[j] * x[3 * std::size_t(s.nodes()[v[j]]) + i];
    d[i] = p[i] - q;
  }
  const double gap = dot(d, n);
  if (!std::isfinite(gap))
    throw std::runtime_error(
        "3D detection: body " + std::to_string(ant) + "'s boundary triangle " +
        std::to_string(best) +
        " or a neighbour has no normal (zero area in the current "
        "configuration): node " +
        std::to_string(node) + " of body " + std::to_string(cand) +
        " cannot be placed against it");
  if (gap > options.alert_distance || gap < -options.max_penetration)
    return false;
  const auto frame = contact_frame(n);
  contact = {
      cand,     node,     ant,      -1, v, nearest.feature, nearest.weights,
      frame[0], frame[1], frame[2], gap};
  return true;
}

std::vector<std::array<int, 2>>
near_surface_pairs(std::span<const BoundarySurface> surfaces,
                   std::span<const double> x, double margin)
{
  std::vector<Box<3>> boxes;
  for (const BoundarySurface& s : surfaces)
    boxes.push_back(points_box<3>(x, s.boundary_nodes(), s.nodes()));
  return overlapping_pairs<3>(boxes, margin);
}

namespace
{
/// A body's triangles' boxes binned on a grid (margin: the search
/// distance), built once per detection for the bodies of the near pairs
struct TriangleGrid
{
  std::vector<Box<3>> boxes;
  std::optional<BoxGrid<3>> grid;

  TriangleGrid(const BoundarySurface& s, std::span<const double> x, double r)
  {
    boxes.reserve(s.triangles().size());
    for (const auto& v : s.triangles())
    {
      Box<3> b = Box<3>::empty();
      for (std::int32_t i : v)
        b.add(&x[3 * std::size_t(s.nodes()[i])]);
      boxes.push_back(b);
    }
    if (!boxes.empty())
      grid.emplace(boxes, r);
  }
};

/// The contacts of the boundary nodes of `cand` (those within the search
/// distance of `ant`'s box) with `ant`'s triangles near them
void body_on_body(std::span<const BoundarySurface> surfaces,
                  std::span<const double> x, const std::vector<Box<3>>& boxes,
                  const TriangleGrid& triangles, int cand, int ant,
                  const DetectionOptions& options,
                  std::vector<Contact3D>& contacts)
{
  if (!triangles.grid)
    return;
  const double r = search_distance(options);
  std::vector<std::int32_t> candidates;
  for (std::int32_t node : surfaces[cand].boundary_nodes())
  {
    const double* p = &x[3 * std::size_t(surfaces[cand].nodes()[node])];
    if (!boxes[ant].contains(p, r))
      continue;
    candidates.clear();
    triangles.grid->near(p,
                         [&](int t)
                         {
                           if (triangles.boxes[t].contains(p, r))
                             candidates.push_back(t);
                         });
    Contact3D c;
    if (node_to_surface(surfaces, x, cand, node, ant, candidates, options, c))
      contacts.push_back(c);
  }
}

/// The node of a 3D contact's triangle the contact point is within a
/// quarter of (weight >= 3/4; the vertex on a vertex), -1 if none
std::int32_t near_node(const Contact3D& c)
{
  for (int k = 0; k < 3; ++k)
    if (c.weights[k] >= 0.75)
      return c.triangle[k];
  return -1;
}
} // namespace

namespace
{
/// detect_contacts_3d's share of the bodies flagged in `mine` (empty:
/// every body's): the pairs whose lower body is flagged and the flagged
/// bodies' wall contacts
std::vector<Contact3D> detect_share(std::span<const BoundarySurface> surfaces,
                                    std::span<const double> x,
                                    const std::vector<PlaneWall>& walls,
                                    const DetectionOptions& options,
                                    std::span<const char> mine)
{
  auto in_share = [&](int b) { return mine.empty() || mine[b]; };
  std::vector<Box<3>> boxes;
  for (const BoundarySurface& s : surfaces)
    boxes.push_back(points_box<3>(x, s.boundary_nodes(), s.nodes()));
  // A node within the search distance of a surface is in its box so
  // inflated: the pairs and the nodes are filtered with that margin
  auto pairs = overlapping_pairs<3>(boxes, search_distance(options));
  std::erase_if(pairs, [&](const auto& p) { return !in_share(p[0]); });
  // The pairs on all cores, each into its own list, joined in pair order:
  // the same list as one thread makes.
  // The triangle grids of the bodies in a near pair, each built once
  std::vector<int> in_pair(surfaces.size(), 0);
  for (const auto& [a, b] : pairs)
    in_pair[a] = in_pair[b] = 1;
  std::vector<std::optional<TriangleGrid>> grids(surfaces.size());
  const auto num_bodies = static_cast<std::int64_t>(surfaces.size());
#pragma omp parallel for schedule(dynamic, 4) if (num_bodies >= 16)
  for (std::int64_t b = 0; b < num_bodies; ++b)
    if (in_pair[b])
      grids[b].emplace(surfaces[b], x, search_distance(options));
  std::vector<std::vector<Contact3D>> by_pair(pairs.size());
  std::vector<std::string> errors(pairs.size());
  const auto num_pairs = static_cast<std::int64_t>(pairs.size());
#pragma omp parallel for schedule(dynamic, 8) if (num_pairs >= 64)
  for (std::int64_t i = 0; i < num_pairs; ++i)
  {
    const auto [a, b] = pairs[i];
    try // an exception must not leave the parallel loop
    {
      body_on_body(surfaces, x, boxes, *grids[b], a, b, options, by_pair[i]);
      body_on_body(surfaces, x, boxes, *grids[a], b, a, options, by_pair[i]);
    }
    catch (const std::exception& e)
    {
      errors[i] = e.what();
    }
    remove_mirrored(by_pair[i], 0, near_node);
  }
  for (const std::string& e : errors)
    if (!e.empty())
      throw std::runtime_error(e);
  std::vector<Contact3D> contacts;
  for (const auto& list : by_pair)
    contacts.insert(contacts.end(), list.begin(), list.end());
  for (int w = 0; w < static_cast<int>(walls.size()); ++w)
  {
    const Vec& p = walls[w].point;
    if (!(std::abs(dot(walls[w].normal, walls[w].normal) - 1) <= 1e-12))
      throw std::invalid_argument("3D detection: wall " + std::to_string(w) +
                                  "'s normal is not a unit vector");
    const auto frame = contact_frame(walls[w].normal);
    for (int b = 0; b < static_cast<int>(surfaces.size()); ++b)
      for (std::int32_t node : surfaces[b].boundary_nodes())
      {
        if (!in_share(b)) // (another share's)
          break;
        const double* xn = &x[3 * std::size_t(surfaces[b].nodes()[node])];
        const double gap = dot(sub(xn, p.data()), frame[0]);
        if (gap <= options.alert_distance && gap >= -options.max_penetration)
          contacts.push_back({b,
                              node,
                              -1,
                              w,
                              {-1, -1, -1},
                              Feature::face,
                              {0, 0, 0},
                              frame[0],
                              frame[1],
                              frame[2],
                              gap});
      }
  }
  return contacts;
}
} // namespace

std::vector<Contact3D> detect_contacts_3d(
    std::span<const BoundarySurface> surfaces, std::span<const double> x,
    const std::vector<PlaneWall>& walls, const DetectionOptions& options)
{
  return detect_share(surfaces, x, walls, options, {});
}

std::vector<Contact3D> detect_contacts_3d(
    const bodies::BodySet& bodies, std::span<const BoundarySurface> surfaces,
    std::span<const double> x, const std::vector<PlaneWall>& walls,
    const DetectionOptions& options)
{
  if (surfaces.size() != static_cast<std::size_t>(bodies.num_bodies()))
    throw std::invalid_argument("detect_contacts_3d: a surface per body");
  std::vector<char> mine(surfaces.size(), 0);
  for (const int b : bodies.local_bodies())
    mine[b] = 1;
  return detect_share(surfaces, x, walls, options, mine);
}

std::int64_t contact_order_key(const Contact3D& c, int num_bodies)
{
  return contact_order_key_of(c, num_bodies);
}

} // namespace softpack::dynamics
