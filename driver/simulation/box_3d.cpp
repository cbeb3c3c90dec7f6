#include "box_3d.h"

#include <algorithm>
#include <cmath>
#include <detection/detection_3d.h>
#include <span>
#include <stdexcept>

namespace softpack::simulation
{

std::vector<dynamics::Wall3D> box_walls_3d(const io::DriverConfig& config)
{
  std::vector<dynamics::Wall3D> walls;
  for (const dynamics::Wall& w : config.walls)
  {
    walls.push_back({w.name,
                     {w.point[0], w.point[1], 0},
                     {w.normal[0], w.normal[1], 0},
                     {w.velocity[0], w.velocity[1], 0}});
    // A servo wall's drive as in 2D (its force in N, its mass in kg)
    walls.back().control = w.control;
    walls.back().pressure = w.pressure;
    walls.back().force = w.force;
    walls.back().mass = w.mass;
  }
  walls.push_back({box_planes_3d[0], {0, 0, 0}, {0, 0, 1}, {0, 0, 0}});
  walls.push_back(
      {box_planes_3d[1], {0, 0, config.box_height}, {0, 0, -1}, {0, 0, 0}});
  return walls;
}

namespace
{
/// The distance between two walls of the box, along the first's normal
double wall_gap(const std::vector<dynamics::Wall3D>& walls,
                const std::string& a, const std::string& b)
{
  auto find = [&](const std::string& name) -> const dynamics::Wall3D&
  {
    for (const dynamics::Wall3D& w : walls)
      if (w.name == name)
        return w;
    throw std::runtime_error("box_3d: no wall named '" + name + "'");
  };
  const dynamics::Wall3D& wa = find(a);
  const dynamics::Wall3D& wb = find(b);
  double d = 0;
  for (int i = 0; i < 3; ++i)
    d += (wb.point[i] - wa.point[i]) * wa.normal[i];
  return d;
}

/// (x_right - x_left) (y_top - y_bottom)
double box_plan_area(const std::vector<dynamics::Wall3D>& walls)
{
  const std::vector<std::string>& names = io::box_wall_names; // l, r, b, t
  return wall_gap(walls, names[0], names[1]) *
         wall_gap(walls, names[2], names[3]);
}
} // namespace

double box_volume(const std::vector<dynamics::Wall3D>& walls)
{
  return box_plan_area(walls) *
         wall_gap(walls, box_planes_3d[0], box_planes_3d[1]);
}

double base_area_fraction(const bodies::BodySet& bodies,
                          const std::vector<dynamics::Wall3D>& walls)
{
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  double area = 0;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    for (const std::array<std::int32_t, 3>& f : body.boundary_faces)
    {
      std::array<std::array<double, 2>, 3> x;
      bool on_base = true;
      for (int k = 0; k < 3; ++k)
      {
        const std::size_t i = 3 * std::size_t(body.nodes[f[k]]);
        on_base = on_base && std::abs(X[i + 2]) <= base_tolerance;
        x[k] = {X[i] + u[i], X[i + 1] + u[i + 1]};
      }
      if (!on_base)
        continue;
      // Outward normal -z: the projected area is -(b - a) x (c - a) . e_z / 2
      area -= 0.5 * ((x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) -
                     (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]));
    }
  }
  return area / box_plan_area(walls);
}

void check_3d_run(MPI_Comm /*comm: any number of ranks*/,
                  const io::DriverConfig& config)
{
  const std::string file = config.file.string() + ": ";
  const std::string tail = " with scene.model.dimension = 3: not yet in 3D "
                           "(docs/bodies_3d.md)";
  if (config.cell)
    throw std::runtime_error(file + "cell.enabled" + tail);
  if (!config.box)
    throw std::runtime_error(file + "scene.box.enabled = false" + tail);
}

void WallForceAverage3D::add_step(const dynamics::MoreauJean& scheme)
{
  const std::vector<std::array<double, 3>> f = scheme.wall_forces_3d();
  _impulse.resize(std::max(_impulse.size(), f.size()), {0, 0, 0});
  const double h = scheme.time_step();
  for (std::size_t w = 0; w < f.size(); ++w)
    for (int i = 0; i < 3; ++i)
      _impulse[w][i] += f[w][i] * h;
  _duration += h;
}

std::vector<std::array<double, 3>>
WallForceAverage3D::forces(std::size_t num_walls) const
{
  std::vector<std::array<double, 3>> out(num_walls, {0, 0, 0});
  if (_duration <= 0)
    return out;
  for (std::size_t w = 0; w < std::min(num_walls, _impulse.size()); ++w)
    for (int i = 0; i < 3; ++i)
      out[w][i] = _impulse[w][i] / _duration;
  return out;
}

void WallForceAverage3D::reset()
{
  _impulse.clear();
  _duration = 0;
}

double max_overlap_depth_3d(const bodies::BodySet& bodies,
                            const std::vector<dynamics::Wall3D>& walls,
                            const dynamics::DetectionOptions& options)
{
  std::vector<dynamics::BoundarySurface> surfaces;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    surfaces.emplace_back(
        std::vector<std::int32_t>(body.nodes.begin(), body.nodes.end()),
        body.boundary_faces);
  }
  std::vector<dynamics::PlaneWall> planes;
  for (const dynamics::Wall3D& w : walls)
    planes.push_back({w.point, w.normal});
  double depth = 0;
  for (const dynamics::Contact3D& c : dynamics::detect_contacts_3d(
           surfaces, bodies.current_coordinates(), planes, options))
    depth = std::max(depth, -c.gap);
  return depth;
}

} // namespace softpack::simulation
