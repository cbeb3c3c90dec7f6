#include "walls.h"

#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{

std::vector<Wall> box_walls(double x0, double x1, double y0, double y1,
                            double piston_speed)
{
  return {
      {"left", {x0, 0}, {1, 0}, {0, 0}},
      {"piston", {x1, 0}, {-1, 0}, {-piston_speed, 0}},
      {"bottom", {0, y0}, {0, 1}, {0, 0}},
      {"top", {0, y1}, {0, -1}, {0, 0}},
  };
}

namespace
{
double dot(const std::array<double, 2>& a, const std::array<double, 2>& b)
{
  return a[0] * b[0] + a[1] * b[1];
}
} // namespace

const char* conflicting_drive(const WallDrive& d)
{
  if (d.control != WallControl::velocity &&
      (d.velocity[0] != 0 || d.velocity[1] != 0))
    return "velocity";
  if (d.control != WallControl::pressure && d.pressure != 0)
    return "pressure";
  if (d.control != WallControl::force && d.force != 0)
    return "force";
  return nullptr;
}

void link_walls(std::vector<Wall>& walls)
{
  constexpr double tol = 1e-9;
  for (std::size_t w = 0; w < walls.size(); ++w)
  {
    Wall& wall = walls[w];
    if (!wall.servo())
      continue;
    if (!(wall.mass > 0) || !std::isfinite(wall.mass))
      throw std::invalid_argument("wall \"" + wall.name +
                                  "\": a servo wall needs a mass > 0");
    if (wall.control != WallControl::pressure)
      continue;
    for (std::size_t a = 0; a < walls.size() && wall.span[0] < 0; ++a)
      for (std::size_t b = a + 1; b < walls.size(); ++b)
        if (std::abs(dot(walls[a].normal, wall.normal)) < tol &&
            std::abs(dot(walls[b].normal, wall.normal)) < tol &&
            dot(walls[a].normal, walls[b].normal) < -1 + tol)
        {
          wall.span = {static_cast<int>(a), static_cast<int>(b)};
          break;
        }
    if (wall.span[0] < 0)
      throw std::invalid_argument(
          "wall \"" + wall.name +
          "\": control pressure needs two facing walls perpendicular to it "
          "(a box) to measure its length");
  }
}

double wall_length(const std::vector<Wall>& walls, std::size_t w)
{
  const Wall &a = walls[walls[w].span[0]], &b = walls[walls[w].span[1]];
  return std::abs((b.point[0] - a.point[0]) * a.normal[0] +
                  (b.point[1] - a.point[1]) * a.normal[1]);
}

double imposed_force(const std::vector<Wall>& walls, std::size_t w)
{
  switch (walls[w].control)
  {
  case WallControl::pressure:
    return walls[w].pressure * wall_length(walls, w);
  case WallControl::force:
    return walls[w].force;
  default:
    return 0;
  }
}

double walls_kinetic_energy(const std::vector<Wall>& walls)
{
  double e = 0;
  for (const Wall& w : walls)
    if (w.servo())
      e += 0.5 * w.mass * dot(w.velocity, w.velocity);
  return e;
}

} // namespace softpack::dynamics
