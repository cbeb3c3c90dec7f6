// What the Moreau–Jean step does for 3D bodies only: the construction with
// plane walls and its refusals, the node-to-face detection of a step and
// the walls' forces (the step itself is moreau_jean.cpp's, for both
// dimensions).
#include "moreau_jean_step.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{

MoreauJean::MoreauJean(bodies::BodySet& bodies, MoreauJeanOptions options,
                       std::vector<Wall3D> walls,
                       parallel::Distribution distribution)
    : MoreauJean(bodies, std::vector<Wall>{}, std::move(options),
                 std::move(distribution))
{
  if (dim() != 3)
    throw std::invalid_argument("MoreauJean: 3D walls for bodies of "
                                "dimension " +
                                std::to_string(dim()));
  for (const Wall3D& w : walls)
  {
    const double norm =
        std::sqrt(w.normal[0] * w.normal[0] + w.normal[1] * w.normal[1] +
                  w.normal[2] * w.normal[2]);
    if (!(std::abs(norm - 1) <= 1e-12))
      throw std::invalid_argument("walls." + w.name +
                                  ".normal: not a unit vector");
    if (!(w.tensile_strength >= 0 && std::isfinite(w.tensile_strength)))
      throw std::invalid_argument("walls." + w.name +
                                  ".tensile_strength: not >= 0");
  }
  _walls3 = std::move(walls);
  link_walls(_walls3);
}

void MoreauJean::check_3d() const
{
  auto refuse = [](const std::string& what)
  {
    throw std::invalid_argument(what + ": not yet in 3D (docs/contact_3d.md, "
                                       "\"The 3D step\")");
  };
  if (!_walls.empty())
    refuse("walls: 2D walls (a 3D run takes Wall3D plane walls)");
  if (_options.friction.cohesive() || _options.friction.bonded())
    refuse("friction: a cohesive or bonded law");
  if (_bodies.internal_stride() > 0)
    refuse("material: a law with internal variables");
}

ContactOperator MoreauJean::detect_3d()
{
  if (_surfaces.empty())
    for (int b = 0; b < _bodies.num_bodies(); ++b)
    {
      const bodies::Body& body = _bodies.body(b);
      _surfaces.emplace_back(
          std::vector<std::int32_t>(body.nodes.begin(), body.nodes.end()),
          body.boundary_faces);
    }
  std::vector<PlaneWall> planes;
  for (const Wall3D& w : _walls3)
    planes.push_back({w.point, w.normal});
  _contacts3 = _exchange.detect(
      _bodies, _surfaces, _bodies.current_coordinates(), planes, _detection);
  return ContactOperator(_contacts3, _walls3);
}

std::vector<double> MoreauJean::wall_cohesion_3d() const
{
  if (std::none_of(_walls3.begin(), _walls3.end(),
                   [](const Wall3D& w) { return w.tensile_strength > 0; }))
    return {};
  std::vector<double> c(_contacts3.size(), 0.0);
  for (std::size_t a = 0; a < _contacts3.size(); ++a)
  {
    const Contact3D& contact = _contacts3[a];
    if (contact.wall >= 0 && std::abs(contact.gap) <= wall3d_closed_gap)
      c[a] = _h * _walls3[contact.wall].tensile_strength;
  }
  return c;
}

std::vector<std::array<double, 3>> MoreauJean::wall_forces_3d() const
{
  std::vector<std::array<double, 3>> force(_walls3.size(), {0, 0, 0});
  for (std::size_t a = 0; a < _contacts3.size(); ++a)
  {
    const Contact3D& c = _contacts3[a];
    if (c.wall < 0)
      continue;
    // The wall receives the opposite of the candidate's impulse.
    for (int i = 0; i < 3; ++i)
      force[c.wall][i] -= (_R[3 * a] * c.n[i] + _R[3 * a + 1] * c.t1[i] +
                           _R[3 * a + 2] * c.t2[i]) /
                          _h;
  }
  return force;
}

} // namespace softpack::dynamics
