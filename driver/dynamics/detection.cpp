#include "detection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace softpack::dynamics
{
namespace
{
struct Box
{
  double x0, y0, x1, y1;
  bool overlaps(const Box& o, double margin) const
  {
    return x0 - margin <= o.x1 && o.x0 - margin <= x1 && y0 - margin <= o.y1
           && o.y0 - margin <= y1;
  }
  bool contains(double x, double y, double margin) const
  {
    return x >= x0 - margin && x <= x1 + margin && y >= y0 - margin
           && y <= y1 + margin;
  }
};

std::vector<Box> body_boxes(const bodies::BodySet& bodies,
                            std::span<const double> x)
{
  std::vector<Box> boxes;
  boxes.reserve(bodies.num_bodies());
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    Box box{inf, inf, -inf, -inf};
    for (std::int32_t local : body.boundary_nodes)
    {
      const std::int32_t g = body.nodes[local];
      box.x0 = std::min(box.x0, x[2 * g]);
      box.x1 = std::max(box.x1, x[2 * g]);
      box.y0 = std::min(box.y0, x[2 * g + 1]);
      box.y1 = std::max(box.y1, x[2 * g + 1]);
    }
    boxes.push_back(box);
  }
  return boxes;
}

/// Nearest segment of `antagonist` to the candidate node, if within the
/// gap window; appends the contact.
void node_to_body(const bodies::BodySet& bodies, std::span<const double> x,
                  int cand_body, std::int32_t cand_node, int ant_body,
                  const DetectionOptions& options,
                  std::vector<Contact>& contacts)
{
  const bodies::Body& cand = bodies.body(cand_body);
  const bodies::Body& ant = bodies.body(ant_body);
  const std::int32_t gc = cand.nodes[cand_node];
  const double px = x[2 * gc], py = x[2 * gc + 1];

  double best_distance = std::numeric_limits<double>::infinity();
  Contact best{};
  for (const auto& seg : ant.boundary_segments)
  {
    const std::int32_t ga = ant.nodes[seg[0]], gb = ant.nodes[seg[1]];
    const double ax = x[2 * ga], ay = x[2 * ga + 1];
    const double tx = x[2 * gb] - ax, ty = x[2 * gb + 1] - ay;
    const double len2 = tx * tx + ty * ty;
    const double xi
        = std::clamp(((px - ax) * tx + (py - ay) * ty) / len2, 0.0, 1.0);
    const double dx = px - (ax + xi * tx), dy = py - (ay + xi * ty);
    const double distance = std::hypot(dx, dy);
    if (distance >= best_distance)
      continue;
    const double len = std::sqrt(len2);
    // Outward normal of a counter-clockwise segment: tangent turned
    // clockwise.
    const std::array<double, 2> n = {ty / len, -tx / len};
    const double gap = dx * n[0] + dy * n[1];
    if (gap > options.alert_distance || gap < -options.max_penetration)
      continue;
    best_distance = distance;
    best = Contact{cand_body, cand_node, ant_body, -1, seg, xi, n,
                   {-n[1], n[0]}, gap};
  }
  if (std::isfinite(best_distance))
    contacts.push_back(best);
}
} // namespace

std::vector<std::array<int, 2>>
near_body_pairs(const bodies::BodySet& bodies, std::span<const double> x,
                double margin)
{
  const std::vector<Box> boxes = body_boxes(bodies, x);
  if (boxes.empty())
    return {};
  double cell = 0, xmin = boxes[0].x0, ymin = boxes[0].y0;
  for (const Box& b : boxes)
  {
    cell = std::max({cell, b.x1 - b.x0 + margin, b.y1 - b.y0 + margin});
    xmin = std::min(xmin, b.x0);
    ymin = std::min(ymin, b.y0);
  }
  // Each box is binned by its lower-left corner; a box spans at most two
  // cells per direction, so neighbours live in the 3x3 surrounding cells.
  auto key = [](std::int64_t i, std::int64_t j) { return (i << 32) ^ j; };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  std::vector<std::array<std::int64_t, 2>> bin(boxes.size());
  for (std::size_t b = 0; b < boxes.size(); ++b)
  {
    bin[b] = {static_cast<std::int64_t>((boxes[b].x0 - xmin) / cell),
              static_cast<std::int64_t>((boxes[b].y0 - ymin) / cell)};
    grid[key(bin[b][0], bin[b][1])].push_back(static_cast<int>(b));
  }
  std::vector<std::array<int, 2>> pairs;
  for (std::size_t a = 0; a < boxes.size(); ++a)
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
      {
        auto it = grid.find(key(bin[a][0] + di, bin[a][1] + dj));
        if (it == grid.end())
          continue;
        for (int b : it->second)
          if (b > static_cast<int>(a) && boxes[a].overlaps(boxes[b], margin))
            pairs.push_back({static_cast<int>(a), b});
      }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<Contact> detect_contacts(const bodies::BodySet& bodies,
                                     std::span<const double> x,
                                     const std::vector<Wall>& walls,
                                     const DetectionOptions& options)
{
  std::vector<Contact> contacts;
  const std::vector<Box> boxes = body_boxes(bodies, x);
  for (const auto& [a, b] : near_body_pairs(bodies, x, options.alert_distance))
  {
    for (const auto& [cand, ant] : {std::pair{a, b}, std::pair{b, a}})
      for (std::int32_t node : bodies.body(cand).boundary_nodes)
      {
        const std::int32_t g = bodies.body(cand).nodes[node];
        if (boxes[ant].contains(x[2 * g], x[2 * g + 1],
                                options.alert_distance))
          node_to_body(bodies, x, cand, node, ant, options, contacts);
      }
  }

  for (int w = 0; w < static_cast<int>(walls.size()); ++w)
  {
    const std::array<double, 2>& p = walls[w].point;
    const std::array<double, 2>& n = walls[w].normal;
    for (int b = 0; b < bodies.num_bodies(); ++b)
      for (std::int32_t node : bodies.body(b).boundary_nodes)
      {
        const std::int32_t g = bodies.body(b).nodes[node];
        const double gap = (x[2 * g] - p[0]) * n[0] + (x[2 * g + 1] - p[1]) * n[1];
        if (gap <= options.alert_distance && gap >= -options.max_penetration)
          contacts.push_back(
              Contact{b, node, -1, w, {-1, -1}, 0.0, n, {-n[1], n[0]}, gap});
      }
  }
  return contacts;
}

} // namespace softpack::dynamics
