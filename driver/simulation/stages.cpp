#include "stages.h"

#include <algorithm>
#include <bodies/body_forces.h>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace softpack::simulation
{
namespace
{
double dot(const std::array<double, 2>& a, const std::array<double, 2>& b)
{
  return a[0] * b[0] + a[1] * b[1];
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

double box_pressure(const std::vector<dynamics::Wall>& walls,
                    const std::vector<std::array<double, 2>>& forces)
{
  const auto& names = io::box_wall_names; // left, right, bottom, top
  int w[4];
  for (int i = 0; i < 4; ++i)
    w[i] = io::wall_index(walls, names[i]);
  // A wall's length is the distance between its two neighbours.
  const double lx = facing_distance(walls, w[0]); // left - right
  const double ly = facing_distance(walls, w[2]); // bottom - top
  auto push = [&](int i) { return -dot(forces[w[i]], walls[w[i]].normal); };
  const double sxx = (push(0) + push(1)) / (2 * ly);
  const double syy = (push(2) + push(3)) / (2 * lx);
  return 0.5 * (sxx + syy);
}

int facing_wall(const std::vector<dynamics::Wall>& walls, int w)
{
  for (std::size_t o = 0; o < walls.size(); ++o)
    if (static_cast<int>(o) != w &&
        dot(walls[o].normal, walls[w].normal) < -1 + 1e-9)
      return static_cast<int>(o);
  return -1;
}

double facing_distance(const std::vector<dynamics::Wall>& walls, int w)
{
  const int f = facing_wall(walls, w);
  if (f < 0)
    return 0;
  const dynamics::Wall &a = walls[w], &b = walls[f];
  return (b.point[0] - a.point[0]) * a.normal[0] +
         (b.point[1] - a.point[1]) * a.normal[1];
}

namespace
{
/// The largest servo wall's residual: its imposed force against the normal
/// contact force it received, relative to the imposed force (a servo wall
/// is a body too)
double servo_wall_ratio(const dynamics::MoreauJean& scheme)
{
  // Measured against its own load: a wall carries the contacts of a whole
  // side of the box (tens of pair forces), so measured against one mean
  // pair force its residual breathing would keep a 100-disk stage from
  // ever ending (seen at 40 kPa: 0.5 % of its load).
  const std::vector<dynamics::Wall>& walls = scheme.walls();
  const std::vector<std::array<double, 2>> received = scheme.wall_forces();
  double ratio = 0;
  for (std::size_t w = 0; w < walls.size(); ++w)
  {
    const double imposed = dynamics::imposed_force(walls, w);
    if (walls[w].servo() && imposed != 0)
      ratio = std::max(ratio,
                       std::abs(imposed + dot(received[w], walls[w].normal)) /
                           std::abs(imposed));
  }
  return ratio;
}
} // namespace

double unbalanced_force_ratio(const dynamics::MoreauJean& scheme,
                              const bodies::BodySet& bodies,
                              const std::array<double, 2>& gravity)
{
  const std::vector<dynamics::Contact>& contacts = scheme.contacts();
  const std::vector<double>& R = scheme.impulses();
  // The particles' ratio is taken on impulses (forces x h), as the
  // contacts give them; the walls' on forces.
  std::vector<std::array<double, 2>> resultant(bodies.num_bodies(), {0, 0});
  if (gravity != std::array<double, 2>{0, 0})
    for (int b = 0; b < bodies.num_bodies(); ++b)
    {
      const std::array<double, 2> w = bodies::body_weight(bodies, b, gravity);
      for (int d = 0; d < 2; ++d)
        resultant[b][d] = w[d] * scheme.time_step();
    }
  // A pair: (candidate, antagonist body) or (candidate, -1 - wall).
  std::map<std::pair<int, int>, std::array<double, 2>> pairs;
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    const dynamics::Contact& c = contacts[a];
    const std::array<double, 2> f = {R[2 * a] * c.n[0] + R[2 * a + 1] * c.t[0],
                                     R[2 * a] * c.n[1] + R[2 * a + 1] * c.t[1]};
    for (int d = 0; d < 2; ++d)
    {
      resultant[c.candidate_body][d] += f[d];
      if (c.antagonist_body >= 0)
        resultant[c.antagonist_body][d] -= f[d];
    }
    // One pair whichever body is the candidate.
    const int other = c.antagonist_body >= 0 ? c.antagonist_body : -1 - c.wall;
    const std::pair<int, int> key =
        other >= 0 ? std::make_pair(std::min(c.candidate_body, other),
                                    std::max(c.candidate_body, other))
                   : std::make_pair(c.candidate_body, other);
    std::array<double, 2>& p = pairs[key];
    // Forces on the lower-numbered body of the pair.
    const double s = (other >= 0 && c.candidate_body != key.first) ? -1 : 1;
    p[0] += s * f[0];
    p[1] += s * f[1];
  }
  double sum = 0;
  int n = 0;
  for (const auto& [key, f] : pairs)
    if (std::hypot(f[0], f[1]) > 0)
    {
      sum += std::hypot(f[0], f[1]);
      ++n;
    }
  double largest = 0;
  for (const auto& f : resultant)
    largest = std::max(largest, std::hypot(f[0], f[1]));
  // No contact force: at rest, unless a weight pulls a body in flight
  if (n == 0)
    return largest > 0 ? std::numeric_limits<double>::infinity() : 0;
  return std::max(largest / (sum / n), servo_wall_ratio(scheme));
}

StageProgram::StageProgram(const io::DriverConfig& config)
    : _stages(config.stages), _cell_drive(config.cell_drive),
      _stage_cells(config.stage_cells),
      _gravity(config.parameters.gravity.acceleration)
{
}

double StageProgram::set_drives(const parameters::Stage& stage,
                                std::vector<dynamics::Wall>& walls)
{
  double returned = 0;
  for (const auto& [name, s] : stage.walls)
  {
    dynamics::Wall& w = walls[io::wall_index(walls, name)];
    const bool was_servo = w.servo();
    w.control = s.control;
    w.pressure = s.pressure;
    w.force = s.force;
    if (!w.servo())
    {
      if (was_servo)
        returned += 0.5 * w.mass * dot(w.velocity, w.velocity);
      w.velocity = s.velocity;
    }
    else if (!was_servo)
      w.velocity = {0, 0}; // a new servo wall starts at rest
    w.span = {-1, -1};
  }
  dynamics::link_walls(walls);
  return returned;
}

void StageProgram::begin(int k, dynamics::MoreauJean& scheme,
                         std::optional<double> phi, const std::string& ended_by)
{
  const parameters::Stage& stage = _stages[k];
  scheme.set_default_friction(stage.contact.friction);
  std::vector<dynamics::Wall> walls = scheme.walls();
  const double returned = set_drives(stage, walls);
  if (returned != 0)
    // The accounts' wall_work is the scheme's: a restore of its own state
    // with that energy taken out (the same arithmetic as a continued run).
    scheme.continue_with(walls,
                         [&](dynamics::SchemeState& s)
                         {
                           s.energy.wall_work -= returned;
                           for (std::size_t w = 0; w < walls.size(); ++w)
                             s.wall_velocities[w] = walls[w].velocity;
                         });
  else
    scheme.walls() = walls;
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
    _start.length = facing_distance(
        scheme.walls(), io::wall_index(scheme.walls(), stage.stop.strain_wall));
  if (phi && stage.stop.packing_fraction > 0)
    _start.phi_side = side(*phi, stage.stop.packing_fraction);
  if (stage.stop.pressure > 0)
    _start.pressure_side =
        side(box_pressure(scheme.walls(), scheme.wall_forces()),
             stage.stop.pressure);
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
    set_drives(_stages[k], scheme.walls());
  // The drive's components before the state's rates (restored next)
  if (!_stage_cells.empty())
    scheme.change_cell_drive(_stage_cells[start.index], start.time);
  scheme.set_default_friction(_stages[start.index].contact.friction);
  _start = start;
}

double StageProgram::strain(const std::vector<dynamics::Wall>& walls) const
{
  const std::string& name = stage().stop.strain_wall;
  if (name.empty() || _start.length == 0)
    return 0;
  const int w = io::wall_index(walls, name);
  return (_start.length - facing_distance(walls, w)) / _start.length;
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
           std::abs(strain(scheme.walls())) >= stop.strain * (1 - 1e-12))
    c.met = "strain";
  else if (stop.pressure > 0 &&
           crossed(box_pressure(scheme.walls(), scheme.wall_forces()),
                   stop.pressure, _start.pressure_side))
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
    out << sep << "strain " << stop.strain << " (strain "
        << strain(scheme.walls()) << ")";
    sep = ", ";
  }
  if (stop.pressure > 0)
  {
    out << sep << "pressure " << stop.pressure << " Pa (P "
        << box_pressure(scheme.walls(), scheme.wall_forces()) << " Pa)";
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
