#include "placement.h"

#include <stdexcept>

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

std::vector<std::array<double, 3>> centroids_3d(const BodySet& bodies)
{
  if (bodies.dim() != 3)
    throw std::invalid_argument("centroids_3d: 3D bodies only");
  const std::vector<double> x = bodies.current_coordinates();
  std::vector<std::array<double, 3>> out(bodies.num_bodies());
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const Body& body = bodies.body(b);
    // Each face and the origin span a tetrahedron of signed volume
    // a . (b x c) / 6 and centroid (a + b + c) / 4.
    double volume = 0;
    std::array<double, 3> moment = {0, 0, 0};
    for (const auto& face : body.boundary_faces)
    {
      const double* p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = &x[3 * body.nodes[face[k]]];
      const double v = (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                        p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                        p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) /
                       6;
      volume += v;
      for (int i = 0; i < 3; ++i)
        moment[i] += v * (p[0][i] + p[1][i] + p[2][i]) / 4;
    }
    for (int i = 0; i < 3; ++i)
      out[b][i] = moment[i] / volume;
  }
  return out;
}

} // namespace softpack::bodies
