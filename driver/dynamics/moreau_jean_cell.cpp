// The periodic cell's part of the scheme (docs/periodic_cell.md): set up,
// and its end of step (the cell advanced, the bodies re-wrapped).
#include "moreau_jean.h"

#include <walls/servo_walls.h>

#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{

void MoreauJean::set_cell(const PeriodicCell& cell)
{
  if (_started)
    throw std::logic_error("MoreauJean::set_cell: after the first step");
  if (dim() != 2)
    throw std::runtime_error("periodic cell ([cell] enabled): not yet in 3D "
                             "(docs/contact_3d.md, \"The 3D step\")");
  if (dist().distributed())
    throw std::runtime_error(
        "periodic cell ([cell] enabled): one MPI rank only for now (run "
        "without --ranks)");
  if (!_rigid.empty())
    throw std::runtime_error("periodic cell ([cell] enabled): rigid "
                             "materials are not supported in a cell yet");
  if (_damping.alpha != 0)
    throw std::runtime_error(
        "periodic cell ([cell] enabled): [damping] alpha must be 0: a "
        "mass-proportional damping acts on the bodies' velocities, which "
        "differ by the cell's rate between a body and its images (beta is "
        "kept)");
  if (!(cell.area() > 0))
    throw std::runtime_error(
        "periodic cell: [cell] a1, a2 must span a positive area, a2 "
        "counter-clockwise from a1 (det h = " +
        std::to_string(cell.area()) + " m^2)");
  _cell = cell;
}

std::vector<std::array<double, 2>> MoreauJean::body_centroids() const
{
  const std::vector<double> x = _bodies.current_coordinates();
  std::vector<std::array<double, 2>> centroids(_bodies.num_bodies());
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = _bodies.body(b);
    std::array<double, 2> c = {0, 0};
    for (const std::int32_t g : body.nodes)
      for (int d = 0; d < 2; ++d)
        c[d] += x[2 * g + d] / static_cast<double>(body.nodes.size());
    centroids[b] = c;
  }
  return centroids;
}

void MoreauJean::finish_cell_step(double h, const ServoWalls& servo)
{
  PeriodicCell& cell = *_cell;
  // The controlled components moved at their mid-step rates, end at V+
  for (const ServoStep& s : servo.cell)
    cell.axis_rate(cell.servo[s.index].axis) = s.v_mid;
  cell.advance(h);
  for (const ServoStep& s : servo.cell)
    cell.axis_rate(cell.servo[s.index].axis) = s.v_new;
  if (!servo.cell.empty() &&
      cell.speed() * _h > _options.contact.alert_distance)
    throw std::runtime_error(
        "step " + std::to_string(_steps) +
        ": the stress-controlled cell's edges move " +
        std::to_string(cell.speed() * _h) +
        " m in a step, more than contact.alert_distance: the cell runs "
        "away (a stress the assembly cannot hold?); make [cell] mass "
        "larger or the time step smaller");
  bool changed = affine_kick(h, servo);
  // The same lattice in a less leaning basis: the contacts' image shifts
  // in it
  if (const int n = cell.remap(); n != 0)
    for (Contact& c : _contacts)
      c.image[0] += n * c.image[1];
  changed = rewrap() || changed;
  if (!changed)
    return;
  // Recomputed as a restore computes them, so that a run continued from
  // this state steps as this one does
  _bodies.internal_force(_f_int);
  _products_valid = false;
  const double kinetic = body_kinetic_energy();
  _energy.rewrap += kinetic - _body_kinetic;
  _body_kinetic = kinetic;
  _energy_stale = true;
}

bool MoreauJean::affine_kick(double h, const ServoWalls& servo)
{
  // The change of the controlled rates over the step, per axis
  std::array<double, 2> delta = {0, 0};
  bool any = false;
  for (const ServoStep& s : servo.cell)
  {
    delta[_cell->servo[s.index].axis] += s.v_new - s.v_old;
    any = any || s.v_new != s.v_old;
  }
  if (!any)
    return false;
  // Each body's velocity changes by the affine field's change at its
  // centroid at the step's start, (delta dh/dt) h^-1 c, as the step's
  // contact problem had it, and its position by th h times that: a body
  // and its images (centroids c + h k) then differ by the new (dh/dt) k, as
  // their images' velocities do (docs/periodic_cell.md)
  const double th = _options.time.theta;
  const std::span<double> u = _bodies.displacement();
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const std::array<double, 2>& s = servo.cell_coordinates[b];
    for (const std::int32_t g : _bodies.body(b).nodes)
      for (int d = 0; d < 2; ++d)
      {
        _v[2 * g + d] += delta[d] * s[d];
        u[2 * g + d] += h * th * delta[d] * s[d];
      }
  }
  return true;
}

bool MoreauJean::rewrap()
{
  const PeriodicCell& cell = *_cell;
  const std::vector<std::array<double, 2>> centroids = body_centroids();
  const std::span<double> u = _bodies.displacement();
  const int nb = _bodies.num_bodies();
  // Each body's move: by -h k, k = floor of its centroid's cell coordinates
  std::vector<ImageShift> moved(nb, {0, 0});
  bool any = false;
  for (int b = 0; b < nb; ++b)
  {
    const std::array<double, 2> s = cell.fractional(centroids[b]);
    const ImageShift k = {static_cast<int>(std::floor(s[0])),
                          static_cast<int>(std::floor(s[1]))};
    if (k[0] == 0 && k[1] == 0)
      continue;
    moved[b] = k;
    any = true;
    // The body takes its image's place and velocity
    const std::array<double, 2> shift = cell.shift(k), rate = cell.rate(k);
    for (const std::int32_t g : _bodies.body(b).nodes)
      for (int d = 0; d < 2; ++d)
      {
        u[2 * g + d] -= shift[d];
        _v[2 * g + d] -= rate[d];
      }
  }
  if (!any)
    return false;
  // The antagonist's image seen from the moved candidate
  for (Contact& c : _contacts)
    if (c.antagonist_body >= 0)
      for (int d = 0; d < 2; ++d)
        c.image[d] += moved[c.antagonist_body][d] - moved[c.candidate_body][d];
  return true;
}

} // namespace softpack::dynamics
