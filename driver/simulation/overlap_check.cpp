#include "overlap_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softpack::simulation
{
namespace
{
using Box = std::array<double, 4>; // xmin, ymin, xmax, ymax

Box bounding_box(const std::vector<Segment>& segments)
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  Box box = {inf, inf, -inf, -inf};
  for (const Segment& s : segments)
  {
    box[0] = std::min({box[0], s[0], s[2]});
    box[1] = std::min({box[1], s[1], s[3]});
    box[2] = std::max({box[2], s[0], s[2]});
    box[3] = std::max({box[3], s[1], s[3]});
  }
  return box;
}

bool intersect(const Box& a, const Box& b)
{
  return a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3];
}

/// Crossing-number test: a horizontal ray to +x crosses the boundary an odd
/// number of times when (x, y) is inside.
bool inside(double x, double y, const std::vector<Segment>& segments)
{
  bool in = false;
  for (const Segment& s : segments)
  {
    if ((s[1] > y) == (s[3] > y))
      continue;
    const double xc = s[0] + (y - s[1]) * (s[2] - s[0]) / (s[3] - s[1]);
    if (xc > x)
      in = !in;
  }
  return in;
}

double distance_to_boundary(double x, double y,
                            const std::vector<Segment>& segments)
{
  double d2 = std::numeric_limits<double>::infinity();
  for (const Segment& s : segments)
  {
    const double ex = s[2] - s[0], ey = s[3] - s[1];
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0 ? ((x - s[0]) * ex + (y - s[1]) * ey) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const double dx = x - s[0] - t * ex, dy = y - s[1] - t * ey;
    d2 = std::min(d2, dx * dx + dy * dy);
  }
  return std::sqrt(d2);
}

/// Deepest node of `a` (its segments' starts) inside `b`.
double depth_inside(const std::vector<Segment>& a,
                    const std::vector<Segment>& b, const Box& box_b)
{
  double depth = 0;
  for (const Segment& s : a)
  {
    const double x = s[0], y = s[1];
    if (x < box_b[0] || x > box_b[2] || y < box_b[1] || y > box_b[3])
      continue;
    if (inside(x, y, b))
      depth = std::max(depth, distance_to_boundary(x, y, b));
  }
  return depth;
}
} // namespace

std::vector<std::vector<Segment>> deformed_boundaries(bodies::BodySet& bodies)
{
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  std::vector<std::vector<Segment>> out(bodies.num_bodies());
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    for (const auto& [i, j] : body.boundary_segments)
    {
      const std::size_t p = 2 * body.nodes[i], q = 2 * body.nodes[j];
      out[b].push_back(
          {X[p] + u[p], X[p + 1] + u[p + 1], X[q] + u[q], X[q + 1] + u[q + 1]});
    }
  }
  return out;
}

namespace
{
/// Segments and box moved by s
std::vector<Segment> moved(const std::vector<Segment>& segments,
                           const std::array<double, 2>& s)
{
  std::vector<Segment> out = segments;
  for (Segment& g : out)
    g = {g[0] + s[0], g[1] + s[1], g[2] + s[0], g[3] + s[1]};
  return out;
}

/// The depth of a's nodes inside b's images near it (a periodic cell: k in
/// {-1, 0, 1}^2, not b itself when b is a)
double depth_in_images(const std::vector<Segment>& a, const Box& box_a,
                       const std::vector<Segment>& b, const Box& box_b,
                       bool same, const dynamics::PeriodicCell& cell)
{
  double depth = 0;
  for (int k0 = -1; k0 <= 1; ++k0)
    for (int k1 = -1; k1 <= 1; ++k1)
    {
      if (same && k0 == 0 && k1 == 0)
        continue;
      const std::array<double, 2> s = cell.shift({k0, k1});
      const Box image = {box_b[0] + s[0], box_b[1] + s[1], box_b[2] + s[0],
                         box_b[3] + s[1]};
      if (intersect(box_a, image))
        depth = std::max(depth, depth_inside(a, moved(b, s), image));
    }
  return depth;
}
} // namespace

double max_overlap_depth(const std::vector<std::vector<Segment>>& boundaries,
                         const std::vector<dynamics::Wall>& walls,
                         const dynamics::PeriodicCell* cell)
{
  std::vector<Box> boxes;
  for (const auto& segments : boundaries)
    boxes.push_back(bounding_box(segments));
  double depth = 0;
  for (std::size_t a = 0; a < boundaries.size(); ++a)
  {
    for (std::size_t b = 0; b < boundaries.size(); ++b)
      if (cell)
        depth = std::max(depth,
                         depth_in_images(boundaries[a], boxes[a], boundaries[b],
                                         boxes[b], a == b, *cell));
      else if (a != b && intersect(boxes[a], boxes[b]))
        depth = std::max(depth,
                         depth_inside(boundaries[a], boundaries[b], boxes[b]));
    for (const dynamics::Wall& w : walls)
      for (const Segment& s : boundaries[a])
        depth = std::max(depth, -((s[0] - w.point[0]) * w.normal[0] +
                                  (s[1] - w.point[1]) * w.normal[1]));
  }
  return depth;
}

} // namespace softpack::simulation
