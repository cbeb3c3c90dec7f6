// What the scheme exposes between steps: its state (to save and continue
// from), the energy accounts and the wall forces of the last step.
#include "moreau_jean.h"

#include <walls/servo_cell.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace softpack::dynamics
{

namespace
{
void require_output(bool current, const char* what)
{
  if (!current)
    throw std::logic_error(
        std::string("MoreauJean::") + what +
        ": a distributed run's processes hold their local bodies' interiors "
        "only (prepare_output first; io::OutputGather gathers the vectors)");
}
} // namespace

const EnergyBalance& MoreauJean::energy() const
{
  if (_energy_stale)
  {
    if (!_strain_shared)
    {
      require_output(!dist().distributed(), "energy");
      _body_strain = _bodies.body_strain_energy();
    }
    _energy.strain =
        std::accumulate(_body_strain.begin(), _body_strain.end(), 0.0);
    _energy.kinetic = _body_kinetic + walls_kinetic_energy(_walls) +
                      walls_kinetic_energy(_walls3) +
                      (_cell ? cell_kinetic_energy(*_cell) : 0.0);
    if (!_started)
      _energy.kinetic0 = _energy.kinetic;
    _energy_stale = false;
  }
  return _energy;
}

SchemeState MoreauJean::state() const
{
  require_output(!dist().distributed(), "state");
  return stored_state();
}

SchemeState MoreauJean::stored_state() const
{
  SchemeState s = scalar_state();
  s.u = _bodies.to_global(std::as_const(_bodies).displacement());
  s.v = _bodies.to_global(_v);
  if (_matrix_age >= 0)
    s.u_tangent = _bodies.to_global(_u_tangent);
  return s;
}

SchemeState MoreauJean::scalar_state() const
{
  SchemeState s;
  s.time = _time;
  s.steps = _steps;
  for (const Wall& w : _walls)
  {
    s.wall_points.push_back(w.point);
    s.wall_velocities.push_back(w.velocity);
  }
  s.reactions = _history.entries();
  s.dim = dim();
  for (const Wall3D& w : _walls3)
  {
    s.wall_points_3d.push_back(w.point);
    s.wall_velocities_3d.push_back(w.velocity);
  }
  s.reactions_3d = _history.entries_3d();
  s.bonds = _bonds.entries();
  s.bonds_formed = _bonds.formed();
  s.energy = energy();
  s.matrix_age = _matrix_age;
  s.last_iterations = _last_iterations;
  s.step_size = _step_size.state();
  if (_cell)
  {
    s.cell = {_cell->a1[0],      _cell->a1[1],      _cell->a2[0],
              _cell->a2[1],      _cell->a1_rate[0], _cell->a1_rate[1],
              _cell->a2_rate[0], _cell->a2_rate[1]};
    // The isotropic mode's V (its rates are in dh/dt, not V itself)
    for (const CellServo& c : _cell->servo)
      if (c.axis == CellServo::mean)
        s.cell.push_back(c.velocity);
  }
  // Whole when serial; a distributed run's share has its local bodies'
  // current (the others' NaN): io::OutputGather gathers them
  const std::span<const double> internal = _bodies.internal_variables();
  s.internal.assign(internal.begin(), internal.end());
  if (_matrix_age >= 0)
    s.internal_tangent = _internal_tangent;
  return s;
}

void MoreauJean::check_internal(const SchemeState& s) const
{
  const std::size_t n = _bodies.internal_variables().size();
  if (s.internal.size() != n)
    throw std::invalid_argument(
        n > 0 && s.internal.empty()
            ? "state: no internal_variables in it, the run's law has them "
              "(viscoelastic_neo_hookean's Maxwell branches): a state of a "
              "run without them cannot continue exactly"
            : "state: internal_variables of " +
                  std::to_string(s.internal.size()) + " values, the run has " +
                  std::to_string(n));
  if (s.matrix_age >= 0 && s.internal_tangent.size() != n)
    throw std::invalid_argument("state: internal_variables of the kept "
                                "tangent of " +
                                std::to_string(s.internal_tangent.size()) +
                                " values, the run has " + std::to_string(n));
}

void MoreauJean::restore_cell(const std::vector<double>& c)
{
  // (4 values: a state written before the rates were kept; the rates are
  // then the run's own; 9: with the isotropic mode's V)
  const std::size_t modes =
      _cell ? std::count_if(_cell->servo.begin(), _cell->servo.end(),
                            [](const CellServo& s)
                            { return s.axis == CellServo::mean; })
            : 0;
  if (_cell ? (c.size() != 4 && c.size() != 8 + modes) : !c.empty())
    throw std::invalid_argument(
        !_cell      ? "state: of a periodic cell, the run has none ([cell])"
        : c.empty() ? "state: no periodic cell in it, the run has one ([cell])"
                    : "state: a cell of " + std::to_string(c.size()) +
                          " values, the run's drive (its stage's) needs " +
                          std::to_string(8 + modes) +
                          " (9 with [cell] control_mean = \"stress\")");
  if (!_cell)
    return;
  _cell->a1 = {c[0], c[1]};
  _cell->a2 = {c[2], c[3]};
  if (c.size() < 8)
    return;
  _cell->a1_rate = {c[4], c[5]};
  _cell->a2_rate = {c[6], c[7]};
  std::size_t k = 8;
  for (CellServo& s : _cell->servo)
    if (s.axis == CellServo::mean)
      s.velocity = c[k++];
}

void MoreauJean::check_state(const SchemeState& s) const
{
  const std::size_t n = _bodies.num_global_dofs();
  if (s.dim != dim())
    throw std::invalid_argument("state: of a " + std::to_string(s.dim) +
                                "D run, the bodies are " +
                                std::to_string(dim()) + "D");
  if (s.u.size() != n || s.v.size() != n)
    throw std::invalid_argument("state: " + std::to_string(s.u.size()) +
                                " DOFs, the bodies have " + std::to_string(n));
  if (s.wall_points.size() != _walls.size())
    throw std::invalid_argument(
        "state: " + std::to_string(s.wall_points.size()) +
        " walls, the run has " + std::to_string(_walls.size()));
  if (s.wall_points_3d.size() != _walls3.size())
    throw std::invalid_argument(
        "state: " + std::to_string(s.wall_points_3d.size()) +
        " plane walls, the run has " + std::to_string(_walls3.size()));
  if (s.matrix_age >= 0 && s.u_tangent.size() != n)
    throw std::invalid_argument("state: a kept tangent of " +
                                std::to_string(s.u_tangent.size()) +
                                " DOFs, the bodies have " + std::to_string(n));
  check_internal(s);
}

void MoreauJean::restore(const SchemeState& s)
{
  check_state(s);
  // (4 values: a state written before the rates were kept; the rates are
  // then the run's own)
  restore_cell(s.cell);
  std::span<double> u = _bodies.displacement();
  // The step first: the kept matrix is rebuilt with the h it was built for.
  _step_size.restore(s.step_size);
  _h = _step_size.current();
  if (s.matrix_age >= 0)
  {
    // The kept iteration matrix, rebuilt where it was assembled: the same
    // arithmetic as the uninterrupted run's refactorization.
    const std::vector<double> u_tangent = _bodies.from_global(s.u_tangent);
    std::copy(u_tangent.begin(), u_tangent.end(), u.begin());
    _bodies.set_internal_variables(s.internal_tangent);
    factorize_tangent(nullptr);
  }
  _bodies.set_internal_variables(s.internal);
  const std::vector<double> u_state = _bodies.from_global(s.u);
  std::copy(u_state.begin(), u_state.end(), u.begin());
  _v = _bodies.from_global(s.v);
  for (std::size_t w = 0; w < _walls.size(); ++w)
  {
    _walls[w].point = s.wall_points[w];
    // A servo wall's velocity is state; a velocity wall keeps the one the
    // run imposes now.
    if (w < s.wall_velocities.size() && _walls[w].servo())
      _walls[w].velocity = s.wall_velocities[w];
  }
  // 3D: the planes' points, and a servo plane's velocity (an imposed one
  // stays the run's, as for a 2D velocity wall)
  for (std::size_t w = 0; w < _walls3.size(); ++w)
  {
    _walls3[w].point = s.wall_points_3d[w];
    if (w < s.wall_velocities_3d.size() && _walls3[w].servo())
      _walls3[w].velocity = s.wall_velocities_3d[w];
  }
  _history.restore(s.reactions);
  _history.restore(s.reactions_3d);
  // (a run without a bonded pair keeps none of the state's bonds)
  _bonds.restore(_options.friction.bonded() ? s.bonds
                                            : std::vector<BondHistory::Entry>{},
                 s.bonds_formed);
  _time = s.time;
  _steps = s.steps;
  _bodies.internal_force(_f_int);
  _rigid.zero(_f_int);
  _energy = s.energy;
  _body_kinetic = body_kinetic_energy();
  _energy_stale = true;
  _strain_shared = false;
  _started = true;
  _matrix_age = s.matrix_age;
  _last_iterations = s.last_iterations;
  // M v and K v are recomputed at the first step from the restored K and v.
  _products_valid = false;
}

void MoreauJean::continue_with(std::vector<Wall> walls,
                               const std::function<void(SchemeState&)>& edit)
{
  SchemeState s = stored_state();
  _walls = std::move(walls);
  continue_edited(s, edit);
}

void MoreauJean::continue_with(std::vector<Wall3D> walls,
                               const std::function<void(SchemeState&)>& edit)
{
  SchemeState s = stored_state();
  _walls3 = std::move(walls);
  continue_edited(s, edit);
}

void MoreauJean::continue_edited(SchemeState& s,
                                 const std::function<void(SchemeState&)>& edit)
{
  edit(s);
  // The displacement and velocity do not change (the entries of the
  // interiors not stored go out and come back NaN): the strain energies
  // stay current.
  const bool strain_shared = _strain_shared;
  restore(s);
  _strain_shared = strain_shared;
}

std::vector<std::array<double, 2>> MoreauJean::wall_forces() const
{
  std::vector<std::array<double, 2>> force(_walls.size(), {0, 0});
  const double h = _h;
  for (std::size_t a = 0; a < _contacts.size(); ++a)
  {
    const Contact& c = _contacts[a];
    if (c.wall < 0)
      continue;
    // The wall receives the opposite of the candidate's impulse.
    force[c.wall][0] -= (_R[2 * a] * c.n[0] + _R[2 * a + 1] * c.t[0]) / h;
    force[c.wall][1] -= (_R[2 * a] * c.n[1] + _R[2 * a + 1] * c.t[1]) / h;
  }
  return force;
}

} // namespace softpack::dynamics
