// The periodic cell's part of the scheme (docs/periodic_cell.md): set up,
// and its end of step (the cell advanced, the bodies re-wrapped).
#include "moreau_jean.h"

#include <walls/servo_cell.h>
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
  if (!_rigid.empty())
    throw std::runtime_error("periodic cell ([cell] enabled): rigid "
                             "materials are not supported in a cell yet");
  if (!(cell.area() > 0))
    throw std::runtime_error(
        "periodic cell: [cell] a1, a2 must span a positive area, a2 "
        "counter-clockwise from a1 (det h = " +
        std::to_string(cell.area()) + " m^2)");
  _cell = cell;
}

void MoreauJean::change_cell_drive(const CellDrive& drive, double start_time)
{
  PeriodicCell& cell = *_cell;
  const PeriodicCell old = cell;
  const PeriodicCell now = PeriodicCell::moving(
      cell.a1, cell.a2, drive.gradient_x, drive.gradient_y);
  cell.a1_rate = now.a1_rate;
  cell.a2_rate = now.a2_rate;
  cell.servo = drive.servo;
  for (CellServo& s : cell.servo)
    s.ramp_start = start_time;
  // A component under stress keeps its rate; the isotropic mode
  // starts at rest (its V = 0: the rates are L h)
  for (CellServo& s : cell.servo)
    if (s.axis != CellServo::mean)
      cell.axis_rate(s.axis) = old.axis_rate(s.axis);
  if (!_started)
    return; // the run's drive from its start (or a state's, restored next)
  // The servo unknowns' kinetic energy that leaves (or enters) the
  // accounts is the loading's, as a servo wall's is
  _energy.cell_work += cell_kinetic_energy(cell) - cell_kinetic_energy(old);
  // Every body takes the change of the affine field at its centroid, so
  // that a body and its images (c + h k) keep the relative velocity
  // (dh/dt) k; its kinetic energy is booked in rewrap, as a re-wrapping's
  const std::array<double, 2> d1 = {cell.a1_rate[0] - old.a1_rate[0],
                                    cell.a1_rate[1] - old.a1_rate[1]};
  const std::array<double, 2> d2 = {cell.a2_rate[0] - old.a2_rate[0],
                                    cell.a2_rate[1] - old.a2_rate[1]};
  const std::vector<std::array<double, 2>> centroids = body_centroids();
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const std::array<double, 2> s = cell.fractional(centroids[b]);
    for (const std::int32_t g : _bodies.body(b).nodes)
      for (int d = 0; d < 2; ++d)
        _v[2 * g + d] += d1[d] * s[0] + d2[d] * s[1];
  }
  _products_valid = false;
  const double kinetic = body_kinetic_energy();
  _energy.rewrap += kinetic - _body_kinetic;
  _body_kinetic = kinetic;
  _energy_stale = true;
}

std::vector<std::array<double, 2>> MoreauJean::body_centroids() const
{
  const std::vector<double> x = _bodies.current_coordinates();
  std::vector<std::array<double, 2>> centroids(_bodies.num_bodies());
  // Each from its owner (the only rank that stores the interior), summed
  // over the ranks with zeros: every rank gets the owner's bits and
  // re-wraps and kicks the boundaries it stores alike
  for (const int b : _bodies.local_bodies())
  {
    const bodies::Body& body = _bodies.body(b);
    std::array<double, 2> c = {0, 0};
    for (const std::int32_t g : body.nodes)
      for (int d = 0; d < 2; ++d)
        c[d] += x[2 * g + d] / static_cast<double>(body.nodes.size());
    centroids[b] = c;
  }
  if (dist().distributed())
    dist().comm().sum(
        std::span<double>(centroids.front().data(), 2 * centroids.size()));
  return centroids;
}

MoreauJean::Vectors MoreauJean::affine_drag() const
{
  if (!_cell || _damping.alpha == 0)
    return {};
  // A body and its images differ in velocity by (dh/dt) k, and so do
  // their affine velocities: the damping acts on the motion relative to
  // the cell's deformation, whichever image represents the body
  const PeriodicCell& cell = *_cell;
  const std::vector<double> x = _bodies.current_coordinates();
  Vectors drag(_bodies.num_bodies());
  for (const int b : _bodies.local_bodies())
  {
    const std::vector<std::int32_t>& nodes = _bodies.body(b).nodes;
    Eigen::VectorXd v_affine(2 * nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
    {
      const std::array<double, 2> s =
          cell.fractional({x[2 * nodes[i]], x[2 * nodes[i] + 1]});
      for (int d = 0; d < 2; ++d)
        v_affine[2 * i + d] = cell.a1_rate[d] * s[0] + cell.a2_rate[d] * s[1];
    }
    drag[b] =
        _damping.alpha * bodies::symmetric_product(_kbar.mass(b), v_affine);
  }
  return drag;
}

void MoreauJean::finish_cell_step(double h, const ServoWalls& servo)
{
  PeriodicCell& cell = *_cell;
  const std::array<double, 2> a1_rate = cell.a1_rate, a2_rate = cell.a2_rate;
  // The controlled components moved at their mid-step rates, end at V+
  set_servo_rates(servo, a1_rate, a2_rate, &ServoStep::v_mid);
  cell.advance(h);
  set_servo_rates(servo, a1_rate, a2_rate, &ServoStep::v_new);
  const std::array<double, 4> rebase = rebase_mean_mode(servo);
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
  changed = mean_mode_kick(h, servo, rebase) || changed;
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

void MoreauJean::set_servo_rates(const ServoWalls& servo,
                                 const std::array<double, 2>& a1_rate,
                                 const std::array<double, 2>& a2_rate,
                                 double ServoStep::*velocity)
{
  PeriodicCell& cell = *_cell;
  for (const ServoStep& s : servo.cell)
  {
    const int axis = cell.servo[s.index].axis;
    if (axis != CellServo::mean)
    {
      cell.axis_rate(axis) = s.*velocity;
      continue;
    }
    // dh/dt = (dh/dt)- + (V - V-) W, W the mode at the step's start
    const double dv = s.*velocity - s.v_old;
    for (int d = 0; d < 2; ++d)
    {
      cell.a1_rate[d] = a1_rate[d] + dv * servo.cell_mode[d];
      cell.a2_rate[d] = a2_rate[d] + dv * servo.cell_mode[2 + d];
    }
    cell.servo[s.index].velocity = s.*velocity;
  }
}

std::array<double, 4> MoreauJean::rebase_mean_mode(const ServoWalls& servo)
{
  // The isotropic mode follows the cell, W = h / sqrt(det h), so that the
  // mode's load is the mean stress at any shape: at the end of the step
  // the rates V+ W become V+ W+, the change (W+ - W) V+ (returned) given to
  // the bodies' affine field as a rate change is (mean_mode_kick)
  PeriodicCell& cell = *_cell;
  std::array<double, 4> change = {0, 0, 0, 0};
  for (const ServoStep& s : servo.cell)
    if (cell.servo[s.index].axis == CellServo::mean)
    {
      const std::array<double, 4> w = isotropic_mode(cell);
      for (int j = 0; j < 4; ++j)
        change[j] = s.v_new * (w[j] - servo.cell_mode[j]);
      for (int d = 0; d < 2; ++d)
      {
        cell.a1_rate[d] += change[d];
        cell.a2_rate[d] += change[2 + d];
      }
    }
  return change;
}

bool MoreauJean::mean_mode_kick(double h, const ServoWalls& servo,
                                const std::array<double, 4>& rebase)
{
  const ServoStep* mean = nullptr;
  for (const ServoStep& s : servo.cell)
    if (_cell->servo[s.index].axis == CellServo::mean)
      mean = &s;
  if (mean == nullptr)
    return false;
  // The step's change (V+ - V-) W s at the velocity and th h times it at
  // the position, as affine_kick's; the rebase's at the velocity only (a
  // change of the rates between two steps)
  const double dv = mean->v_new - mean->v_old;
  const double th = _options.time.theta;
  const std::span<double> u = _bodies.displacement();
  for (int b = 0; b < _bodies.num_bodies(); ++b)
  {
    const std::array<double, 2>& s = servo.cell_coordinates[b];
    const std::array<double, 2> ws = servo.mode_times(s);
    const std::array<double, 2> rs = {rebase[0] * s[0] + rebase[2] * s[1],
                                      rebase[1] * s[0] + rebase[3] * s[1]};
    for (const std::int32_t g : _bodies.body(b).nodes)
      for (int d = 0; d < 2; ++d)
      {
        _v[2 * g + d] += dv * ws[d] + rs[d];
        u[2 * g + d] += h * th * dv * ws[d];
      }
  }
  return true;
}

bool MoreauJean::affine_kick(double h, const ServoWalls& servo)
{
  // The change of the controlled rates over the step, per axis, and of
  // h_xy's (its velocity change at a body is dV e_x s_y)
  std::array<double, 2> delta = {0, 0};
  double shear = 0;
  bool any = false, sheared = false;
  for (const ServoStep& s : servo.cell)
  {
    const int axis = _cell->servo[s.index].axis;
    if (axis == CellServo::mean)
      continue; // mean_mode_kick
    if (axis == CellServo::shear_xy)
    {
      shear += s.v_new - s.v_old;
      sheared = true;
    }
    else
      delta[axis] += s.v_new - s.v_old;
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
    if (sheared)
      for (const std::int32_t g : _bodies.body(b).nodes)
      {
        _v[2 * g] += shear * s[1];
        u[2 * g] += h * th * shear * s[1];
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
