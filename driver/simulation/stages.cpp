#include "stages.h"
#include "run_support.h"
#include <walls/wall_vectors.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>
#include <type_traits>

namespace softpack::simulation
{
using dynamics::dot;

namespace
{

/// The index of the wall named `name` (io::wall_index, for either
/// dimension's walls)
template <class W>
int index_of(const std::vector<W>& walls, const std::string& name)
{
  for (std::size_t i = 0; i < walls.size(); ++i)
    if (walls[i].name == name)
      return static_cast<int>(i);
  throw std::runtime_error("no wall named '" + name + "'");
}

/// A run's walls of either dimension: a 3D run's plane walls, else the
/// 2D walls (the same stage logic works on both)
template <class F>
decltype(auto) with_walls(const dynamics::MoreauJean& scheme, F&& f)
{
  if (scheme.dimension() == 3)
    return f(scheme.walls_3d(), scheme.wall_forces_3d());
  return f(scheme.walls(), scheme.wall_forces());
}

/// The side of `target` a value starts on: +1 below (or at), -1 above.
int side(double value, double target)
{
  return value <= target ? 1 : -1;
}

/// Whether a value has reached `target` from its side.
bool crossed(double value, double target, int from)
{
  return from * (value - target) >= 0;
}
} // namespace

namespace
{
template <class W> int facing_wall_d(const std::vector<W>& walls, int w)
{
  for (std::size_t o = 0; o < walls.size(); ++o)
    if (static_cast<int>(o) != w &&
        dot(walls[o].normal, walls[w].normal) < -1 + 1e-9)
      return static_cast<int>(o);
  return -1;
}

template <class W> double facing_distance_d(const std::vector<W>& walls, int w)
{
  const int f = facing_wall_d(walls, w);
  if (f < 0)
    return 0;
  const W &a = walls[w], &b = walls[f];
  double d = (b.point[0] - a.point[0]) * a.normal[0];
  for (std::size_t i = 1; i < a.point.size(); ++i)
    d += (b.point[i] - a.point[i]) * a.normal[i];
  return d;
}

template <class W, class F>
double box_pressure_d(const std::vector<W>& walls, const std::vector<F>& forces)
{
  const auto& names = io::box_wall_names; // left, right, bottom, top
  int w[4];
  for (int i = 0; i < 4; ++i)
    w[i] = index_of(walls, names[i]);
  // A wall's length is the distance between its two neighbours; in 3D its
  // area that times the box's height (base to lid).
  const double lx = facing_distance_d(walls, w[0]); // left - right
  const double ly = facing_distance_d(walls, w[2]); // bottom - top
  double depth = 1;
  if constexpr (std::tuple_size_v<F> == 3)
    depth = facing_distance_d(walls, index_of(walls, "base"));
  auto push = [&](int i) { return -dot(forces[w[i]], walls[w[i]].normal); };
  const double sxx = (push(0) + push(1)) / (2 * (ly * depth));
  const double syy = (push(2) + push(3)) / (2 * (lx * depth));
  return 0.5 * (sxx + syy);
}
} // namespace

double box_pressure(const std::vector<dynamics::Wall>& walls,
                    const std::vector<std::array<double, 2>>& forces)
{
  return box_pressure_d(walls, forces);
}

double box_pressure(const std::vector<dynamics::Wall3D>& walls,
                    const std::vector<std::array<double, 3>>& forces)
{
  return box_pressure_d(walls, forces);
}

int facing_wall(const std::vector<dynamics::Wall>& walls, int w)
{
  return facing_wall_d(walls, w);
}

double facing_distance(const std::vector<dynamics::Wall>& walls, int w)
{
  return facing_distance_d(walls, w);
}

double facing_distance(const std::vector<dynamics::Wall3D>& walls, int w)
{
  return facing_distance_d(walls, w);
}

StageProgram::StageProgram(const io::DriverConfig& config)
    : _stages(config.stages), _cell_drive(config.cell_drive),
      _stage_cells(config.stage_cells), _gravity(gravity(config))
{
}

namespace
{
/// A stage's velocity for a wall of either dimension (in the x-y plane)
template <class V> V velocity_of(const std::array<double, 2>& v)
{
  V out{};
  out[0] = v[0];
  out[1] = v[1];
  return out;
}

/// Set a stage's drives on walls of either dimension; the kinetic energy of
/// servo walls turned velocity-driven
template <class W>
double set_drives_d(const parameters::Stage& stage, std::vector<W>& walls)
{
  double returned = 0;
  for (const auto& [name, s] : stage.walls)
  {
    W& w = walls[index_of(walls, name)];
    const bool was_servo = w.servo();
    w.control = s.control;
    w.pressure = s.pressure;
    w.force = s.force;
    if (!w.servo())
    {
      if (was_servo)
        returned += 0.5 * w.mass * dot(w.velocity, w.velocity);
      w.velocity = velocity_of<decltype(w.velocity)>(s.velocity);
    }
    else if (!was_servo)
      w.velocity = {}; // a new servo wall starts at rest
    w.span.fill(-1);
  }
  dynamics::link_walls(walls);
  return returned;
}

/// A stage's drives on the scheme's walls of either dimension: a restore
/// of its own state with the returned kinetic energy taken out of
/// wall_work when a servo wall stops (the same arithmetic as a continued
/// run), else the walls replaced
template <class W>
void apply_drives(const parameters::Stage& stage, dynamics::MoreauJean& scheme,
                  std::vector<W> walls)
{
  const double returned = set_drives_d(stage, walls);
  if (returned == 0)
  {
    if constexpr (std::is_same_v<W, dynamics::Wall>)
      scheme.walls() = walls;
    else
      scheme.walls_3d() = walls;
    return;
  }
  scheme.continue_with(walls,
                       [&](dynamics::SchemeState& s)
                       {
                         s.energy.wall_work -= returned;
                         for (std::size_t w = 0; w < walls.size(); ++w)
                           if constexpr (std::is_same_v<W, dynamics::Wall>)
                             s.wall_velocities[w] = walls[w].velocity;
                           else
                             s.wall_velocities_3d[w] = walls[w].velocity;
                       });
}
} // namespace

double StageProgram::set_drives(const parameters::Stage& stage,
                                dynamics::MoreauJean& scheme)
{
  if (scheme.dimension() == 3)
    return set_drives_d(stage, scheme.walls_3d());
  return set_drives_d(stage, scheme.walls());
}

double StageProgram::wall_distance(const dynamics::MoreauJean& scheme,
                                   const std::string& name)
{
  return with_walls(scheme,
                    [&](const auto& walls, const auto&) {
                      return facing_distance_d(walls, index_of(walls, name));
                    });
}

double StageProgram::pressure(const dynamics::MoreauJean& scheme)
{
  return with_walls(scheme, [](const auto& walls, const auto& forces)
                    { return box_pressure_d(walls, forces); });
}

void StageProgram::begin(int k, dynamics::MoreauJean& scheme,
                         std::optional<double> phi, const std::string& ended_by)
{
  const parameters::Stage& stage = _stages[k];
  scheme.set_default_friction(stage.contact.friction);
  if (scheme.dimension() == 3)
    apply_drives(stage, scheme, scheme.walls_3d());
  else
    apply_drives(stage, scheme, scheme.walls());
  // A cell's drive changes at a stage that gives another one
  if (!_stage_cells.empty() &&
      !_stage_cells[k].same(k == 0 ? _cell_drive : _stage_cells[k - 1]))
    scheme.change_cell_drive(_stage_cells[k], scheme.time());
  std::vector<std::string> ended = std::move(_start.ended_by);
  if (!ended_by.empty())
    ended.push_back(ended_by);
  _start = {};
  _start.ended_by = std::move(ended);
  _start.index = k;
  _start.step = scheme.steps();
  _start.time = scheme.time();
  _start.wall_work = scheme.energy().wall_work;
  _start.external_work = scheme.energy().external_work;
  _start.cell_work = scheme.energy().cell_work;
  if (!stage.stop.strain_wall.empty())
    _start.length = wall_distance(scheme, stage.stop.strain_wall);
  if (phi && stage.stop.packing_fraction > 0)
    _start.phi_side = side(*phi, stage.stop.packing_fraction);
  if (stage.stop.pressure > 0)
    _start.pressure_side = side(pressure(scheme), stage.stop.pressure);
  if (stage.bond) // (after continue_with, which restores the flag)
    scheme.form_bonds(true);
}

bool StageProgram::forms_bonds() const
{
  return std::any_of(_stages.begin(), _stages.end(),
                     [](const parameters::Stage& s) { return s.bond; });
}

void StageProgram::resume(const StageStart& start, dynamics::MoreauJean& scheme)
{
  for (int k = 0; k <= start.index; ++k)
    set_drives(_stages[k], scheme);
  // The drive's components before the state's rates (restored next)
  if (!_stage_cells.empty())
    scheme.change_cell_drive(_stage_cells[start.index], start.time);
  scheme.set_default_friction(_stages[start.index].contact.friction);
  _start = start;
}

double StageProgram::strain(const dynamics::MoreauJean& scheme) const
{
  const std::string& name = stage().stop.strain_wall;
  if (name.empty() || _start.length == 0)
    return 0;
  return (_start.length - wall_distance(scheme, name)) / _start.length;
}

Balance StageProgram::balance(const dynamics::MoreauJean& scheme,
                              const bodies::BodySet& bodies) const
{
  const dynamics::EnergyBalance& e = scheme.energy();
  const double work =
      std::abs(e.wall_work - _start.wall_work + e.external_work -
               _start.external_work + (e.cell_work - _start.cell_work));
  Balance b;
  b.kinetic =
      work > 0 ? e.kinetic / work
               : (e.kinetic > 0 ? std::numeric_limits<double>::infinity() : 0);
  b.force = unbalanced_force_ratio(scheme, bodies, _gravity);
  return b;
}

StageCheck StageProgram::check(const dynamics::MoreauJean& scheme,
                               const bodies::BodySet& bodies,
                               std::optional<double> phi,
                               bool output_step) const
{
  const parameters::StageStop& stop = stage().stop;
  StageCheck c;
  if (phi && stop.packing_fraction > 0 &&
      crossed(*phi, stop.packing_fraction, _start.phi_side))
    c.met = "packing_fraction";
  else if (stop.strain > 0 &&
           std::abs(strain(scheme)) >= stop.strain * (1 - 1e-12))
    c.met = "strain";
  else if (stop.pressure > 0 &&
           crossed(pressure(scheme), stop.pressure, _start.pressure_side))
    c.met = "pressure";
  else if (stop.equilibrium > 0 && output_step)
  {
    const Balance b = balance(scheme, bodies);
    if (b.kinetic < stop.equilibrium && b.force < stop.equilibrium)
      c.met = "equilibrium";
  }
  if (!c.met.empty())
    return c;
  if (scheme.time() - _start.time >= stop.max_time * (1 - 1e-12))
  {
    const bool other = stop.packing_fraction > 0 || stop.strain > 0 ||
                       stop.pressure > 0 || stop.equilibrium > 0;
    if (other)
      c.timed_out = true;
    else
      c.met = "max_time";
  }
  return c;
}

std::string StageProgram::missed(const dynamics::MoreauJean& scheme,
                                 const bodies::BodySet& bodies,
                                 std::optional<double> phi) const
{
  const parameters::StageStop& stop = stage().stop;
  std::ostringstream out;
  out << "stage " << _start.index << " \"" << stage().name
      << "\" reached its max_time " << stop.max_time << " s before";
  const char* sep = " ";
  if (stop.packing_fraction > 0)
  {
    out << sep << "packing_fraction " << stop.packing_fraction << " (Phi "
        << (phi ? *phi : 0) << ")";
    sep = ", ";
  }
  if (stop.strain > 0)
  {
    out << sep << "strain " << stop.strain << " (strain " << strain(scheme)
        << ")";
    sep = ", ";
  }
  if (stop.pressure > 0)
  {
    out << sep << "pressure " << stop.pressure << " Pa (P " << pressure(scheme)
        << " Pa)";
    sep = ", ";
  }
  if (stop.equilibrium > 0)
  {
    const Balance b = balance(scheme, bodies);
    out << sep << "equilibrium " << stop.equilibrium << " (K/W " << b.kinetic
        << ", unbalanced force " << b.force << ")";
  }
  return out.str();
}

std::filesystem::path stage_record_path(const std::filesystem::path& state)
{
  return state.parent_path() / (state.stem().string() + ".stage.json");
}

void write_stage_record(const std::filesystem::path& path, long step,
                        const StageStart& s, const std::string& name)
{
  const nlohmann::json j = {{"step", step},
                            {"stage", s.index},
                            {"name", name},
                            {"start_step", s.step},
                            {"start_time", s.time},
                            {"start_wall_work", s.wall_work},
                            {"start_external_work", s.external_work},
                            {"start_cell_work", s.cell_work},
                            {"start_length", s.length},
                            {"phi_side", s.phi_side},
                            {"pressure_side", s.pressure_side},
                            {"ended_by", s.ended_by}};
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << std::setprecision(17) << j.dump(2) << '\n';
    if (!out)
      throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

StageStart read_stage_record(const std::filesystem::path& path, long step,
                             int stages)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(
        path.string() + ": missing: a run with stages continues only from a "
                        "state whose stage record (written next to it) is "
                        "there");
  StageStart s;
  try
  {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("step").get<long>() != step)
      throw std::runtime_error("it is of step " +
                               std::to_string(j.at("step").get<long>()) +
                               ", the state of step " + std::to_string(step));
    s.index = j.at("stage").get<int>();
    s.step = j.at("start_step").get<long>();
    s.time = j.at("start_time").get<double>();
    s.wall_work = j.at("start_wall_work").get<double>();
    // (records written before gravity existed: no external work)
    s.external_work = j.value("start_external_work", 0.0);
    s.cell_work = j.value("start_cell_work", 0.0);
    s.length = j.at("start_length").get<double>();
    s.phi_side = j.at("phi_side").get<int>();
    s.pressure_side = j.at("pressure_side").get<int>();
    // (records written before it was kept: each earlier stage unknown)
    s.ended_by = j.contains("ended_by")
                     ? j.at("ended_by").get<std::vector<std::string>>()
                     : std::vector<std::string>(std::max(s.index, 0), "?");
  }
  catch (const std::exception& e)
  {
    throw std::runtime_error(
        path.string() + ": not the stage record of this state: " + e.what());
  }
  if (s.index < 0 || s.index >= stages)
    throw std::runtime_error(path.string() + ": stage " +
                             std::to_string(s.index) + " of a run with " +
                             std::to_string(stages) + " stages");
  return s;
}

} // namespace softpack::simulation
