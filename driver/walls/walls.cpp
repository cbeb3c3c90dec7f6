#include "walls.h"
#include "wall_vectors.h"

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

/// The first two facing walls (normals opposite) both perpendicular to
/// `normal`, neither of them `used`; {-1, -1} if none
template <class W, class N>
std::array<int, 2> facing_pair(const std::vector<W>& walls, const N& normal,
                               const std::array<int, 2>& used = {-1, -1})
{
  constexpr double tol = 1e-9;
  auto free = [&](std::size_t a)
  { return static_cast<int>(a) != used[0] && static_cast<int>(a) != used[1]; };
  for (std::size_t a = 0; a < walls.size(); ++a)
    for (std::size_t b = a + 1; b < walls.size(); ++b)
      if (free(a) && free(b) && std::abs(dot(walls[a].normal, normal)) < tol &&
          std::abs(dot(walls[b].normal, normal)) < tol &&
          dot(walls[a].normal, walls[b].normal) < -1 + tol)
        return {static_cast<int>(a), static_cast<int>(b)};
  return {-1, -1};
}

/// A servo wall's mass > 0, or refused naming it
template <class W> void check_mass(const W& wall)
{
  if (!(wall.mass > 0) || !std::isfinite(wall.mass))
    throw std::invalid_argument("wall \"" + wall.name +
                                "\": a servo wall needs a mass > 0");
}

/// The distance between walls a and b along a's normal
template <class W> double span_distance(const W& a, const W& b)
{
  double d = 0;
  for (std::size_t i = 0; i < a.point.size(); ++i)
    d += (b.point[i] - a.point[i]) * a.normal[i];
  return std::abs(d);
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
  for (Wall& wall : walls)
  {
    if (!wall.servo())
      continue;
    check_mass(wall);
    if (wall.control != WallControl::pressure)
      continue;
    wall.span = facing_pair(walls, wall.normal);
    if (wall.span[0] < 0)
      throw std::invalid_argument(
          "wall \"" + wall.name +
          "\": control pressure needs two facing walls perpendicular to it "
          "(a box) to measure its length");
  }
}

void link_walls(std::vector<Wall3D>& walls)
{
  for (Wall3D& wall : walls)
  {
    if (!wall.servo())
      continue;
    check_mass(wall);
    if (wall.control != WallControl::pressure)
      continue;
    const std::array<int, 2> first = facing_pair(walls, wall.normal);
    const std::array<int, 2> second =
        first[0] < 0 ? first : facing_pair(walls, wall.normal, first);
    if (second[0] < 0)
      throw std::invalid_argument(
          "wall \"" + wall.name +
          "\": control pressure needs two pairs of facing walls "
          "perpendicular to it (a box) to measure its area");
    wall.span = {first[0], first[1], second[0], second[1]};
  }
}

double wall_area(const std::vector<Wall3D>& walls, std::size_t w)
{
  const std::array<int, 4>& s = walls[w].span;
  return span_distance(walls[s[0]], walls[s[1]]) *
         span_distance(walls[s[2]], walls[s[3]]);
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

double imposed_force(const std::vector<Wall3D>& walls, std::size_t w)
{
  switch (walls[w].control)
  {
  case WallControl::pressure:
    return walls[w].pressure * wall_area(walls, w);
  case WallControl::force:
    return walls[w].force;
  default:
    return 0;
  }
}

double walls_kinetic_energy(const std::vector<Wall3D>& walls)
{
  double e = 0;
  for (const Wall3D& w : walls)
    if (w.servo())
      e += 0.5 * w.mass * dot(w.velocity, w.velocity);
  return e;
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
