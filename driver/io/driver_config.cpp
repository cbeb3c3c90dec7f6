#include "driver_config.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace softpack::io
{
namespace
{
using json = nlohmann::json;

/// Errors that name the file and the key path.
class Reader
{
public:
  explicit Reader(std::string file) : _file(std::move(file)) {}

  const std::string& file() const { return _file; }

  [[noreturn]] void fail(const std::string& path, const std::string& what) const
  {
    throw std::runtime_error(_file + ": " + path + ": " + what);
  }

  /// Require an object with exactly these keys.
  void keys(const json& j, const std::string& path,
            const std::vector<std::string>& keys) const
  {
    std::string allowed;
    for (const std::string& k : keys)
      allowed += (allowed.empty() ? "" : ", ") + k;
    const std::string where = path.empty() ? "(top level)" : path;
    if (!j.is_object())
      fail(where, "must be a table with the keys " + allowed);
    const std::string prefix = path.empty() ? "" : path + ".";
    for (const std::string& k : keys)
      if (!j.contains(k))
        fail(prefix + k, "missing (" + where + " needs " + allowed + ")");
    for (const auto& item : j.items())
      if (std::find(keys.begin(), keys.end(), item.key()) == keys.end())
        fail(prefix + item.key(),
             "unknown key (" + where + " has " + allowed + ")");
  }

  std::string string(const json& v, const std::string& path) const
  {
    if (!v.is_string() || v.get<std::string>().empty())
      fail(path, "= " + v.dump() + " must be a non-empty string");
    return v.get<std::string>();
  }

private:
  std::string _file;
};

json parse(const std::filesystem::path& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path.string() + ": cannot be read");
  try
  {
    return json::parse(in);
  }
  catch (const json::parse_error& e)
  {
    throw std::runtime_error(path.string() + ": not valid JSON: " + e.what());
  }
}

/// walls: every entry read by the reader generated from the schema's
/// [walls]; names unique, normals normalised, one drive per wall.
void read_walls(const Reader& r, const json& walls, DriverConfig& c, bool cell)
{
  if (!walls.is_array() || (walls.empty() && !cell))
    r.fail("walls", "must be a non-empty list of walls (none: a periodic "
                    "cell, cell.enabled)");
  parameters::read(walls, c.walls, r.file());
  for (std::size_t i = 0; i < c.walls.size(); ++i)
  {
    dynamics::Wall& wall = c.walls[i];
    const std::string p = "walls[" + std::to_string(i) + "]";
    for (std::size_t o = 0; o < i; ++o)
      if (c.walls[o].name == wall.name)
        r.fail(p + ".name", "\"" + wall.name + "\" names two walls");
    const double len = std::hypot(wall.normal[0], wall.normal[1]);
    if (!(len > 0) || !std::isfinite(len))
      r.fail(p + ".normal", "must be a nonzero vector");
    wall.normal = {wall.normal[0] / len, wall.normal[1] / len};
    check_drive(wall, r.file(), p);
  }
}

/// stages: each read by the generated reader (every key explicit: the
/// Python config derives them); the walls they name checked here.
void read_stages(const Reader& r, const json& stages, DriverConfig& c)
{
  parameters::read(stages, c.stages, r.file());
  for (std::size_t i = 0; i < c.stages.size(); ++i)
  {
    const std::string p = "stages[" + std::to_string(i) + "]";
    const parameters::Stage& stage = c.stages[i];
    auto named = [&](const std::string& name)
    {
      return std::any_of(c.walls.begin(), c.walls.end(),
                         [&](const dynamics::Wall& w)
                         { return w.name == name; });
    };
    for (const auto& [name, drive] : stage.walls)
    {
      if (!named(name))
        r.fail(p + ".walls." + name, "no such wall");
      check_drive(drive, r.file(), p + ".walls." + name);
    }
    const parameters::StageStop& s = stage.stop;
    if (!s.strain_wall.empty() && !named(s.strain_wall))
      r.fail(p + ".stop.strain_wall",
             "= \"" + s.strain_wall + "\" names no wall");
    if (s.strain > 0 && s.strain_wall.empty())
      r.fail(p + ".stop.strain_wall", "must name a wall when strain > 0");
    if ((s.packing_fraction > 0 && !c.box && !c.parameters.cell.enabled) ||
        (s.pressure > 0 && !c.box))
      r.fail(p + ".stop", "packing_fraction needs a box (scene.box.enabled) "
                          "or a cell, pressure a box");
  }
}

/// A cell's drive ([cell], or a stage's cell.*; docs/periodic_cell.md, "A
/// stress-controlled cell" and "Mean stress"): an imposed rate of a
/// stress-controlled component, a tilting edge a1, a stress on an imposed
/// component and the mean stress with a diagonal one refused, naming the
/// keys (the Python stage refuses them first). `key`: "cell." or
/// "stages[k].cell.".
template <typename Drive>
dynamics::CellDrive read_cell_drive(const Reader& r, const Drive& p,
                                    const std::string& key, double mass,
                                    double damping)
{
  dynamics::CellDrive drive{p.velocity_gradient_x, p.velocity_gradient_y, {}};
  const std::array<std::pair<const std::string*, double>, 2> axes = {
      {{&p.control_xx, p.stress_xx}, {&p.control_yy, p.stress_yy}}};
  const std::array<double, 2> rates = {p.velocity_gradient_x[0],
                                       p.velocity_gradient_y[1]};
  for (int i = 0; i < 2; ++i)
  {
    const std::string axis = i == 0 ? "xx" : "yy";
    if (*axes[i].first != "stress")
    {
      if (axes[i].second != 0)
        r.fail(key + "stress_" + axis, "is given with " + key + "control_" +
                                           axis +
                                           " = \"velocity\": set "
                                           "control_" +
                                           axis + " = \"stress\"");
      continue;
    }
    if (rates[i] != 0)
      r.fail(key + "control_" + axis,
             "= \"stress\" with an imposed rate L_" + axis + " != 0 (" + key +
                 "velocity_gradient_*): the rate is the unknown");
    if (p.velocity_gradient_y[0] != 0)
      r.fail(key + "control_" + axis,
             "= \"stress\" needs L_yx = 0 (" + key +
                 "velocity_gradient_y[0]): the edge a1 stays along x");
    drive.servo.push_back({i, axes[i].second, mass});
  }
  if (p.control_xy != "stress")
  {
    if (p.stress_xy != 0)
      r.fail(key + "stress_xy",
             "is given with " + key + "control_xy = \"velocity\"");
  }
  else if (p.velocity_gradient_x[1] != 0 || p.velocity_gradient_y[0] != 0)
    r.fail(key + "control_xy",
           "= \"stress\" with an imposed L_xy or L_yx != 0 (" + key +
               "velocity_gradient_x[1], velocity_gradient_y[0]): the rate "
               "of h_xy is the unknown, the edge a1 stays along x");
  else
    drive.servo.push_back({dynamics::CellServo::shear_xy, p.stress_xy, mass});
  if (p.control_mean != "stress")
  {
    if (p.stress_mean != 0)
      r.fail(key + "stress_mean",
             "is given with " + key + "control_mean = \"velocity\"");
  }
  else if (!drive.servo.empty())
    r.fail(key + "control_mean", "= \"stress\" with a stress-controlled "
                                 "component (xx, yy or xy): control one or "
                                 "the other");
  else
    drive.servo.push_back({dynamics::CellServo::mean, p.stress_mean, mass});
  if (!drive.servo.empty() && !(mass > 0))
    r.fail("cell.mass", "must be > 0 with a stress-controlled component");
  if (p.stress_rate != 0 && drive.servo.empty())
    r.fail(key + "stress_rate",
           "is given without a stress-controlled component (" + key +
               "control_xx, control_yy, control_xy or control_mean)");
  for (dynamics::CellServo& s : drive.servo)
  {
    s.damping = damping;
    s.stress_rate = p.stress_rate;
  }
  return drive;
}

/// cell: a periodic cell excludes the box and the walls, refused naming the
/// keys; its drive and each stage's.
void read_cell(const Reader& r, DriverConfig& c)
{
  const parameters::Cell& p = c.parameters.cell;
  if (!p.enabled)
  {
    for (const std::string axis : {"xx", "yy", "xy", "mean"})
    {
      const std::string& control = axis == "xx"   ? p.control_xx
                                   : axis == "yy" ? p.control_yy
                                   : axis == "xy" ? p.control_xy
                                                  : p.control_mean;
      if (control == "stress")
        r.fail("cell.control_" + axis,
               "= \"stress\" with cell.enabled = false: no cell degree of "
               "freedom to control");
    }
    return;
  }
  if (c.box)
    r.fail("cell.enabled", "= true with scene.box.enabled = true: a "
                           "periodic cell has no walls (set [box] enabled "
                           "= false)");
  if (!c.walls.empty())
    r.fail("walls", "a periodic cell (cell.enabled) has no walls: both "
                    "directions are periodic (walls." +
                        c.walls.front().name + " given)");
  c.cell = dynamics::PeriodicCell::moving(p.a1, p.a2, p.velocity_gradient_x,
                                          p.velocity_gradient_y);
  if (!(c.cell->area() > 0))
    r.fail("cell.a1", "and cell.a2 must span a positive area, a2 "
                      "counter-clockwise from a1");
  // c = m / tau: the cell's velocity relaxes over tau under its damping
  const double damping = p.damping_time > 0 ? p.mass / p.damping_time : 0.0;
  c.cell_drive = read_cell_drive(r, p, "cell.", p.mass, damping);
  c.cell->servo = c.cell_drive.servo;
  for (std::size_t k = 0; k < c.stages.size(); ++k)
  {
    const std::string key = "stages[" + std::to_string(k) + "].";
    const parameters::StageStop& s = c.stages[k].stop;
    if (s.strain > 0 || s.pressure > 0)
      r.fail(key + "stop", "strain and pressure are measured on walls; a "
                           "cell has none");
    c.stage_cells.push_back(
        read_cell_drive(r, c.stages[k].cell, key + "cell.", p.mass, damping));
  }
}

/// scene.model.dimension and scene.box.height (absent from the records
/// written before 3D scenes: 2D, no height).
void read_dimension(const Reader& r, const json& scene, DriverConfig& c)
{
  const json& model = scene.at("model");
  if (model.is_object() && model.contains("dimension"))
  {
    const json& d = model.at("dimension");
    if (!d.is_number_integer() || (d.get<long>() != 2 && d.get<long>() != 3))
      r.fail("scene.model.dimension", "= " + d.dump() + ": must be 2 or 3");
    c.dimension = d.get<int>();
  }
  const json& box = scene.at("box");
  if (box.contains("height"))
  {
    const json& h = box.at("height");
    if (!h.is_number() || !(h.get<double>() >= 0))
      r.fail("scene.box.height", "= " + h.dump() + ": must be a number >= 0");
    c.box_height = h.get<double>();
  }
  if (c.dimension == 2 && c.box_height != 0)
    r.fail("scene.box.height", "must be 0 in 2D (scene.model.dimension = 2)");
  if (c.dimension == 3 && c.box && !(c.box_height > 0))
    r.fail("scene.box.height", "must be > 0 in 3D (the box's edge along z)");
}

/// scene: the driver uses model.dimension, box.enabled, box.height and
/// bodies; the rest is the scene stage's record, kept for raw/setup.json.
void read_scene(const Reader& r, const json& scene, DriverConfig& c)
{
  // The scene stage's sections (named by the schema) and the bodies.
  std::vector<std::string> keys = parameters::scene_sections;
  keys.push_back("bodies");
  r.keys(scene, "scene", keys);
  const json& box = scene.at("box");
  if (!box.is_object() || !box.contains("enabled") ||
      !box.at("enabled").is_boolean())
    r.fail("scene.box.enabled", "missing or not true/false");
  c.box = box.at("enabled").get<bool>();
  read_dimension(r, scene, c);
  const json& species = scene.at("species");
  if (!species.is_array() || species.empty())
    r.fail("scene.species", "must be a non-empty list of species");
  const json& bodies = scene.at("bodies");
  r.keys(bodies, "scene.bodies", {"mesh", "species"});
  c.mesh = r.string(bodies.at("mesh"), "scene.bodies.mesh");
  const json& index = bodies.at("species");
  if (!index.is_array())
    r.fail("scene.bodies.species", "must be a list (one index per body)");
  for (std::size_t b = 0; b < index.size(); ++b)
  {
    const json& s = index[b];
    if (!s.is_number_integer() || s.get<long>() < 0 ||
        s.get<long>() >= static_cast<long>(species.size()))
      r.fail("scene.bodies.species[" + std::to_string(b) + "]",
             "= " + s.dump() + " is not an index of scene.species (0.." +
                 std::to_string(species.size() - 1) + ")");
    c.body_species.push_back(s.get<int>());
  }
  c.scene = scene;
}
} // namespace

int wall_index(const std::vector<dynamics::Wall>& walls,
               const std::string& name)
{
  for (std::size_t i = 0; i < walls.size(); ++i)
    if (walls[i].name == name)
      return static_cast<int>(i);
  throw std::runtime_error("no wall named '" + name + "'");
}

void check_drive(const dynamics::WallDrive& drive, const std::string& file,
                 const std::string& path)
{
  if (const char* key = dynamics::conflicting_drive(drive))
    throw std::runtime_error(
        file + ": " + path +
        ": a wall is driven by one of velocity, pressure or force: only the "
        "value of control = \"" +
        parameters::name_of(drive.control) + "\" may be nonzero (" + key +
        " is not)");
}

double fastest_wall_speed(const std::vector<dynamics::Wall>& walls)
{
  double fastest = 0;
  for (const dynamics::Wall& w : walls)
    fastest = std::max(fastest, std::hypot(w.velocity[0], w.velocity[1]));
  // With every wall fixed there is no imposed speed to measure velocity
  // errors against; 1 mm/s is small next to any compaction of the paper's
  // kind (piston 0.1 m/s, single-disk plate 0.01 m/s).
  return fastest > 0 ? fastest : 1e-3;
}

DriverConfig read_driver_config(const std::filesystem::path& path)
{
  const json doc = parse(path);
  const Reader r(path.string());
  std::vector<std::string> keys = {"schema_version", "directory",
                                   "initial_state", "scene"};
  keys.insert(keys.end(), parameters::driver_sections.begin(),
              parameters::driver_sections.end());
  r.keys(doc, "", keys);
  const json& version = doc.at("schema_version");
  if (version != parameters::schema_version)
    r.fail("schema_version", "= " + version.dump() +
                                 "; this driver reads version " +
                                 std::to_string(parameters::schema_version));
  DriverConfig c;
  c.file = path;
  c.directory = r.string(doc.at("directory"), "directory");
  if (!doc.at("initial_state").is_null())
    c.initial_state = r.string(doc.at("initial_state"), "initial_state");
  read_scene(r, doc.at("scene"), c);
  // (an empty list is a periodic cell's: checked with the cell)
  const json& cell = doc.at("cell");
  read_walls(r, doc.at("walls"), c,
             cell.is_object() && cell.value("enabled", false) == true);
  parameters::read(doc, c.parameters, r.file());
  c.body_materials = read_body_materials(doc, c);
  c.friction = read_friction_table(doc, c);
  c.materials = doc.at("materials");
  c.friction_pairs = doc.at("friction");
  if (c.box)
    for (const std::string& name : box_wall_names)
      if (std::none_of(c.walls.begin(), c.walls.end(),
                       [&](const dynamics::Wall& w) { return w.name == name; }))
        r.fail("walls", "scene.box.enabled needs a wall named \"" + name +
                            "\" (the box walls are left, right, bottom, top)");
  if (c.parameters.stop.packing_fraction > 0 && !c.box &&
      !c.parameters.cell.enabled)
    r.fail("stop.packing_fraction",
           "> 0 needs a box (scene.box.enabled) or a cell (cell.enabled): "
           "Phi is measured inside it");
  read_stages(r, doc.at("stages"), c);
  c.stage_program = doc.at("stages");
  read_cell(r, c);
  if (c.parameters.stop.base_area_fraction > 0 && c.dimension != 3)
    r.fail("stop.base_area_fraction",
           "> 0 needs scene.model.dimension = 3 (the bottom faces of "
           "standing cylinders on the base)");
  if (!c.stages.empty() && c.parameters.stop.packing_fraction > 0)
    r.fail("stop.packing_fraction",
           "must be 0 with stages (each stage has its own)");
  std::vector<dynamics::Wall> moving = c.walls;
  for (const parameters::Stage& stage : c.stages)
    for (const auto& [name, drive] : stage.walls)
      moving.push_back({"", {0, 0}, {1, 0}, drive.velocity});
  c.velocity_scale = fastest_wall_speed(moving);
  if (c.cell && c.walls.empty())
  {
    // The fastest edges of the cell's drives, at the initial cell
    double speed = c.cell->speed();
    for (const dynamics::CellDrive& d : c.stage_cells)
      speed = std::max(
          speed, dynamics::PeriodicCell::moving(c.cell->a1, c.cell->a2,
                                                d.gradient_x, d.gradient_y)
                     .speed());
    if (speed > 0)
      c.velocity_scale = speed;
  }
  return c;
}

void check_body_count(const DriverConfig& config, int num_bodies)
{
  if (static_cast<int>(config.body_species.size()) != num_bodies)
    throw std::runtime_error(config.file.string() +
                             ": scene.bodies.species: has " +
                             std::to_string(config.body_species.size()) +
                             " entries, the mesh " + config.mesh.string() +
                             " has " + std::to_string(num_bodies) + " bodies");
}

} // namespace softpack::io
