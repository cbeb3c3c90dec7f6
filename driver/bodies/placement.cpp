#include "placement.h"

#include <array>
#include <cmath>

namespace softpack::bodies
{
namespace
{
/// Area centroid of a body's boundary polygon at positions x(node, c)
template <typename Position>
std::array<double, 2> polygon_centroid(const Body& body, Position x)
{
  double twice_area = 0, cx = 0, cy = 0;
  for (const auto& [p, q] : body.boundary_segments)
  {
    const double cross = x(p, 0) * x(q, 1) - x(q, 0) * x(p, 1);
    twice_area += cross;
    cx += (x(p, 0) + x(q, 0)) * cross;
    cy += (x(p, 1) + x(q, 1)) * cross;
  }
  return {cx / (3 * twice_area), cy / (3 * twice_area)};
}
} // namespace

std::vector<Placement> placements(const BodySet& bodies)
{
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  std::vector<Placement> out(bodies.num_bodies());
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const Body& body = bodies.body(b);
    auto reference = [&](std::int32_t local, int c)
    { return X[2 * body.nodes[local] + c]; };
    auto current = [&](std::int32_t local, int c)
    {
      const std::int32_t g = body.nodes[local];
      return X[2 * g + c] + u[2 * g + c];
    };
    const std::array<double, 2> c0 = polygon_centroid(body, reference);
    const std::array<double, 2> c = polygon_centroid(body, current);
    // The angle maximising sum R(theta) a . b over the boundary nodes:
    // tan(theta) = sum a x b / sum a . b.
    double dot = 0, cross = 0;
    for (const auto& segment : body.boundary_segments)
    {
      const std::int32_t n = segment[0];
      const double ax = reference(n, 0) - c0[0], ay = reference(n, 1) - c0[1];
      const double bx = current(n, 0) - c[0], by = current(n, 1) - c[1];
      dot += ax * bx + ay * by;
      cross += ax * by - ay * bx;
    }
    out[b] = {c[0], c[1], std::atan2(cross, dot)};
  }
  return out;
}

} // namespace softpack::bodies
