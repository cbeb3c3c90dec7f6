// The periodic cell's part of the scheme (docs/periodic_cell.md): set up,
// and its end of step (the cell advanced, the bodies re-wrapped).
#include "moreau_jean.h"

#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{

void MoreauJean::set_cell(const PeriodicCell& cell)
{
  if (_started)
    throw std::logic_error("MoreauJean::set_cell: after the first step");
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

void MoreauJean::finish_cell_step(double h)
{
  PeriodicCell& cell = *_cell;
  cell.advance(h);
  const std::vector<double> x = _bodies.current_coordinates();
  const std::span<double> u = _bodies.displacement();
  const int nb = _bodies.num_bodies();
  // Each body's move: by -h k, k = floor of its centroid's cell coordinates
  std::vector<ImageShift> moved(nb, {0, 0});
  bool any = false;
  for (int b = 0; b < nb; ++b)
  {
    const bodies::Body& body = _bodies.body(b);
    std::array<double, 2> c = {0, 0};
    for (const std::int32_t g : body.nodes)
      for (int d = 0; d < 2; ++d)
        c[d] += x[2 * g + d] / static_cast<double>(body.nodes.size());
    const std::array<double, 2> s = cell.fractional(c);
    const ImageShift k = {static_cast<int>(std::floor(s[0])),
                          static_cast<int>(std::floor(s[1]))};
    if (k[0] == 0 && k[1] == 0)
      continue;
    moved[b] = k;
    any = true;
    // The body takes its image's place and velocity
    const std::array<double, 2> shift = cell.shift(k), rate = cell.rate(k);
    for (const std::int32_t g : body.nodes)
      for (int d = 0; d < 2; ++d)
      {
        u[2 * g + d] -= shift[d];
        _v[2 * g + d] -= rate[d];
      }
  }
  if (!any)
    return;
  // The antagonist's image seen from the moved candidate
  for (Contact& c : _contacts)
    if (c.antagonist_body >= 0)
      for (int d = 0; d < 2; ++d)
        c.image[d] += moved[c.antagonist_body][d] - moved[c.candidate_body][d];
  // Recomputed as a restore computes them, so that a run continued from
  // this state steps as this one does
  _bodies.internal_force(_f_int);
  _products_valid = false;
  const double kinetic = body_kinetic_energy();
  _energy.rewrap += kinetic - _body_kinetic;
  _body_kinetic = kinetic;
  _energy_stale = true;
}

} // namespace softpack::dynamics
