#include "detection.h"
#include "box_grid.h"
#include "contact_order.h"
#include "mirrored.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

namespace softpack::dynamics
{
namespace
{
using Box2 = Box<2>;

std::vector<Box2> body_boxes(const bodies::BodySet& bodies,
                             std::span<const double> x)
{
  std::vector<Box2> boxes;
  boxes.reserve(bodies.num_bodies());
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    boxes.push_back(points_box<2>(x, body.boundary_nodes, body.nodes));
  }
  return boxes;
}

/// Outward unit normal of a counter-clockwise boundary segment (the
/// tangent turned clockwise).
std::array<double, 2> segment_normal(std::span<const double> x, std::int32_t ga,
                                     std::int32_t gb)
{
  const double tx = x[2 * gb] - x[2 * ga], ty = x[2 * gb + 1] - x[2 * ga + 1];
  const double len = std::hypot(tx, ty);
  return {ty / len, -tx / len};
}

/// The antagonist's boundary feature nearest to a point: the nearest
/// segment that the point projects onto (-1: none) and the nearest vertex,
/// with their squared distances
struct NearestFeature
{
  double face_distance2 = std::numeric_limits<double>::infinity();
  double vertex_distance2 = std::numeric_limits<double>::infinity();
  std::int32_t face = -1, vertex = -1;
  double face_xi = 0;
};

NearestFeature nearest_feature(const bodies::Body& ant,
                               std::span<const double> x, double px, double py)
{
  // Squared distances: the nearest feature is the same, without a square
  // root per segment (std::hypot here was half of the detection's time)
  NearestFeature f;
  for (std::size_t k = 0; k < ant.boundary_segments.size(); ++k)
  {
    const auto& seg = ant.boundary_segments[k];
    const std::int32_t ga = ant.nodes[seg[0]], gb = ant.nodes[seg[1]];
    const double ax = x[2 * ga], ay = x[2 * ga + 1];
    const double tx = x[2 * gb] - ax, ty = x[2 * gb + 1] - ay;
    const double length2 = tx * tx + ty * ty;
    const double xi = ((px - ax) * tx + (py - ay) * ty) / length2;
    if (xi >= 0 && xi <= 1)
    {
      const double cross = (px - ax) * ty - (py - ay) * tx;
      const double d2 = cross * cross / length2;
      if (d2 < f.face_distance2)
      {
        f.face_distance2 = d2;
        f.face = static_cast<std::int32_t>(k);
        f.face_xi = xi;
      }
    }
    const double dv2 = (px - ax) * (px - ax) + (py - ay) * (py - ay);
    if (dv2 < f.vertex_distance2)
    {
      f.vertex_distance2 = dv2;
      f.vertex = seg[0];
    }
  }
  return f;
}

/// Contact of a candidate node with the nearest feature of the antagonist's
/// boundary: a face (the node projects inside a segment) or, in the shadow
/// of a convex vertex, the vertex itself with the bisector of its two
/// segments' normals as the contact normal. Appends the contact if the gap
/// is within the window [-max_penetration, alert_distance]. Against the
/// image of the antagonist shifted by `offset` = h k (a periodic cell), the
/// candidate point is moved by -offset instead: the gap, normal and xi are
/// the same.
void node_to_body(const bodies::BodySet& bodies, std::span<const double> x,
                  int cand_body, std::int32_t cand_node, int ant_body,
                  const DetectionOptions& options,
                  std::vector<Contact>& contacts, const ImageShift& image,
                  const std::array<double, 2>& offset)
{
  const bodies::Body& ant = bodies.body(ant_body);
  const std::int32_t gc = bodies.body(cand_body).nodes[cand_node];
  const double px = x[2 * gc] - offset[0], py = x[2 * gc + 1] - offset[1];
  const auto [face_distance2, vertex_distance2, face, vertex, face_xi] =
      nearest_feature(ant, x, px, py);
  Contact c{cand_body, cand_node, ant_body, -1, {-1, -1},
            0.0,       {0, 0},    {0, 0},   0.0};
  if (face >= 0 && face_distance2 <= vertex_distance2)
  {
    const auto& seg = ant.boundary_segments[face];
    c.segment = seg;
    c.xi = face_xi;
    c.n = segment_normal(x, ant.nodes[seg[0]], ant.nodes[seg[1]]);
  }
  else if (vertex >= 0)
  {
    const auto& next = ant.boundary_segments[ant.segment_from[vertex]];
    const auto& prev = ant.boundary_segments[ant.segment_to[vertex]];
    const auto n1 = segment_normal(x, ant.nodes[next[0]], ant.nodes[next[1]]);
    const auto n0 = segment_normal(x, ant.nodes[prev[0]], ant.nodes[prev[1]]);
    const double len = std::hypot(n0[0] + n1[0], n0[1] + n1[1]);
    c.segment = next;
    c.xi = 0;
    c.vertex = true;
    c.n = {(n0[0] + n1[0]) / len, (n0[1] + n1[1]) / len};
  }
  else
    return;
  const std::int32_t ga = ant.nodes[c.segment[0]], gb = ant.nodes[c.segment[1]];
  const double qx = (1 - c.xi) * x[2 * ga] + c.xi * x[2 * gb];
  const double qy = (1 - c.xi) * x[2 * ga + 1] + c.xi * x[2 * gb + 1];
  c.gap = (px - qx) * c.n[0] + (py - qy) * c.n[1];
  c.t = {-c.n[1], c.n[0]};
  c.image = image;
  if (c.gap <= options.alert_distance && c.gap >= -options.max_penetration)
    contacts.push_back(c);
}
/// The 2D form of remove_mirrored (mirrored.h): the node within a quarter
/// segment of the contact point, or the vertex
void remove_mirrored_contacts(std::vector<Contact>& contacts, std::size_t first)
{
  remove_mirrored(contacts, first,
                  [](const Contact& c) -> std::int32_t
                  {
                    if (c.vertex || c.xi <= 0.25)
                      return c.segment[0];
                    if (c.xi >= 0.75)
                      return c.segment[1];
                    return -1;
                  });
}
} // namespace

std::vector<std::array<int, 2>> near_body_pairs(const bodies::BodySet& bodies,
                                                std::span<const double> x,
                                                double margin)
{
  return overlapping_pairs<2>(body_boxes(bodies, x), margin);
}

std::vector<ImagePair> near_image_pairs(const bodies::BodySet& bodies,
                                        std::span<const double> x,
                                        double margin, const PeriodicCell& cell)
{
  const std::vector<Box2> boxes = body_boxes(bodies, x);
  for (std::size_t b = 0; b < boxes.size(); ++b)
    check_body_fits(
        cell, static_cast<int>(b),
        {boxes[b].hi[0] - boxes[b].lo[0], boxes[b].hi[1] - boxes[b].lo[1]});
  // Every body's box shifted to its 9 nearest images, k in {-1, 0, 1}^2,
  // kept only if it reaches the region the bodies occupy: an image beyond
  // it is near no body, and most images of the bodies away from the
  // cell's edges are (the grid then holds about N boxes, not 9 N).
  Box2 occupied = boxes.empty() ? Box2{{0, 0}, {0, 0}} : boxes.front();
  for (const Box2& o : boxes)
    occupied = {
        {std::min(occupied.lo[0], o.lo[0]), std::min(occupied.lo[1], o.lo[1])},
        {std::max(occupied.hi[0], o.hi[0]), std::max(occupied.hi[1], o.hi[1])}};
  std::vector<Box2> images;
  std::vector<std::pair<int, ImageShift>> owner;
  for (std::size_t b = 0; b < boxes.size(); ++b)
    for (int k0 = -1; k0 <= 1; ++k0)
      for (int k1 = -1; k1 <= 1; ++k1)
      {
        const std::array<double, 2> s = cell.shift({k0, k1});
        const Box2& o = boxes[b];
        const Box2 image{{o.lo[0] + s[0], o.lo[1] + s[1]},
                         {o.hi[0] + s[0], o.hi[1] + s[1]}};
        if (!occupied.overlaps(image, margin))
          continue;
        images.push_back(image);
        owner.push_back({static_cast<int>(b), {k0, k1}});
      }
  if (images.empty())
    return {};
  const BoxGrid<2> grid(images, margin);
  std::vector<ImagePair> pairs;
  for (std::size_t a = 0; a < boxes.size(); ++a)
    grid.near(boxes[a].lo.data(),
              [&](int i)
              {
                const auto& [b, k] = owner[i];
                if (b > static_cast<int>(a) &&
                    boxes[a].overlaps(images[i], margin))
                  pairs.push_back({static_cast<int>(a), b, k});
              });
  std::sort(pairs.begin(), pairs.end());
  for (std::size_t i = 1; i < pairs.size(); ++i)
    if (pairs[i].a == pairs[i - 1].a && pairs[i].b == pairs[i - 1].b)
      throw std::runtime_error(
          "periodic cell: bodies " + std::to_string(pairs[i].a) + " and " +
          std::to_string(pairs[i].b) +
          " are near through two images: the cell is too small or too "
          "sheared for them");
  return pairs;
}

std::vector<Contact> detect_contacts(const bodies::BodySet& bodies,
                                     std::span<const double> x,
                                     const std::vector<Wall>& walls,
                                     const DetectionOptions& options,
                                     const PeriodicCell* cell)
{
  const std::vector<Box2> boxes = body_boxes(bodies, x);
  std::vector<ImagePair> pairs;
  if (cell)
    pairs = near_image_pairs(bodies, x, options.alert_distance, *cell);
  else
    for (const auto& [a, b] :
         near_body_pairs(bodies, x, options.alert_distance))
      pairs.push_back({a, b, {0, 0}});
  // The pairs on all cores, each into its own list, joined in pair order:
  // the same list as one thread makes.
  std::vector<std::vector<Contact>> by_pair(pairs.size());
  const auto num_pairs = static_cast<std::int64_t>(pairs.size());
#pragma omp parallel for schedule(dynamic, 8) if (num_pairs >= 64)
  for (std::int64_t i = 0; i < num_pairs; ++i)
  {
    const auto [a, b, k] = pairs[i];
    if (!bodies.is_local(a))
      continue;
    // b's image at +h k against a; a's image at -h k against b
    const std::array<double, 2> s =
        cell ? cell->shift(k) : std::array<double, 2>{0, 0};
    const ImageShift minus_k = {-k[0], -k[1]};
    for (const auto& [cand, ant, image, offset] :
         {std::tuple{a, b, k, s},
          std::tuple{b, a, minus_k, std::array{-s[0], -s[1]}}})
      for (std::int32_t node : bodies.body(cand).boundary_nodes)
      {
        const std::int32_t g = bodies.body(cand).nodes[node];
        const std::array<double, 2> p = {x[2 * g] - offset[0],
                                         x[2 * g + 1] - offset[1]};
        if (boxes[ant].contains(p.data(), options.alert_distance))
          node_to_body(bodies, x, cand, node, ant, options, by_pair[i], image,
                       offset);
      }
    remove_mirrored_contacts(by_pair[i], 0);
  }
  std::vector<Contact> contacts;
  for (const std::vector<Contact>& list : by_pair)
    contacts.insert(contacts.end(), list.begin(), list.end());

  for (int w = 0; w < static_cast<int>(walls.size()); ++w)
  {
    const std::array<double, 2>& p = walls[w].point;
    const std::array<double, 2>& n = walls[w].normal;
    for (const int b : bodies.local_bodies())
    {
      for (std::int32_t node : bodies.body(b).boundary_nodes)
      {
        const std::int32_t g = bodies.body(b).nodes[node];
        const double gap =
            (x[2 * g] - p[0]) * n[0] + (x[2 * g + 1] - p[1]) * n[1];
        if (gap <= options.alert_distance && gap >= -options.max_penetration)
          contacts.push_back(
              Contact{b, node, -1, w, {-1, -1}, 0.0, n, {-n[1], n[0]}, gap});
      }
    }
  }
  return contacts;
}

std::int64_t contact_order_key(const Contact& c, int num_bodies)
{
  return contact_order_key_of(c, num_bodies);
}

} // namespace softpack::dynamics
