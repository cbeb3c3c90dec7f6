#include "driver_config.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace softpack::io
{
namespace
{
using json = nlohmann::json;

/// Typed access with errors that name the file and the key path.
class Reader
{
public:
  explicit Reader(std::filesystem::path file) : _file(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const
  {
    throw std::runtime_error(_file.string() + ": " + key + ": " + what);
  }

  const json& at(const json& j, const std::string& key,
                 const std::string& path) const
  {
    if (!j.is_object() || !j.contains(key))
      fail(path + key, "missing");
    return j.at(key);
  }

  double number(const json& j, const std::string& key, const std::string& path,
                double min = -1e300, double max = 1e300) const
  {
    const json& v = at(j, key, path);
    if (!v.is_number())
      fail(path + key, "must be a number");
    const double x = v.get<double>();
    if (!(x >= min && x <= max))
      fail(path + key, "= " + std::to_string(x) + " is out of range [" +
                           std::to_string(min) + ", " + std::to_string(max) +
                           "]");
    return x;
  }

  std::string string(const json& j, const std::string& key,
                     const std::string& path) const
  {
    const json& v = at(j, key, path);
    if (!v.is_string())
      fail(path + key, "must be a string");
    return v.get<std::string>();
  }

  std::array<double, 2> pair(const json& j, const std::string& key,
                             const std::string& path) const
  {
    const json& v = at(j, key, path);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() ||
        !v[1].is_number())
      fail(path + key, "must be a pair of numbers [x, y]");
    return {v[0].get<double>(), v[1].get<double>()};
  }

private:
  std::filesystem::path _file;
};

std::vector<dynamics::Wall> read_walls(const Reader& r, const json& doc)
{
  const json& walls = r.at(doc, "walls", "");
  if (!walls.is_array())
    r.fail("walls", "must be a list");
  std::vector<dynamics::Wall> out;
  for (std::size_t i = 0; i < walls.size(); ++i)
  {
    const std::string p = "walls[" + std::to_string(i) + "].";
    dynamics::Wall w{
        r.string(walls[i], "name", p), r.pair(walls[i], "point", p),
        r.pair(walls[i], "normal", p), r.pair(walls[i], "velocity", p)};
    const double len = std::hypot(w.normal[0], w.normal[1]);
    if (!(len > 0))
      r.fail(p + "normal", "must be nonzero");
    w.normal = {w.normal[0] / len, w.normal[1] / len};
    out.push_back(w);
  }
  return out;
}

void read_stepping(const Reader& r, const json& doc,
                   dynamics::MoreauJeanOptions& o)
{
  const json& t = r.at(doc, "time_stepping", "");
  const std::string p = "time_stepping.";
  o.time_step = r.number(t, "time_step", p, 1e-12, 1);
  o.theta = r.number(t, "theta", p, 0.5, 1);
  const std::string mass = r.string(t, "mass", p);
  if (mass != "consistent" && mass != "lumped")
    r.fail(p + "mass", "must be \"consistent\" or \"lumped\"");
  o.lumped_mass = mass == "lumped";
  o.alpha = r.number(t, "rayleigh_alpha", p, 0);
  o.beta = r.number(t, "rayleigh_beta", p, 0);
  o.newton_tolerance = r.number(t, "newton_tolerance", p, 1e-16, 1);
  o.max_newton_iterations =
      static_cast<int>(r.number(t, "newton_max_iterations", p, 1, 1000));
  const json& full = r.at(t, "full_newton", p);
  if (!full.is_boolean())
    r.fail(p + "full_newton", "must be true or false");
  o.full_newton = full.get<bool>();
  o.velocity_scale = r.number(t, "velocity_scale", p, 0);
  // Optional keys (older driver.json files do not have them).
  if (t.contains("tangent_reuse_steps"))
    o.tangent_reuse_steps =
        static_cast<int>(r.number(t, "tangent_reuse_steps", p, 1, 1e9));
  if (t.contains("refactor_above_iterations"))
    o.refactor_above_iterations =
        static_cast<int>(r.number(t, "refactor_above_iterations", p, 1, 1000));

  const json& c = r.at(doc, "contact", "");
  const std::string q = "contact.";
  o.friction = r.number(c, "friction", q, 0);
  o.detection.alert_distance = r.number(c, "alert_distance", q, 0);
  o.detection.max_penetration = r.number(c, "max_penetration", q, 0);
  o.nlgs.tolerance = r.number(c, "nlgs_tolerance", q, 1e-16, 1);
  o.nlgs.max_sweeps = static_cast<int>(r.number(c, "nlgs_max_sweeps", q, 1));
  o.nlgs.relaxation = r.number(c, "nlgs_relaxation", q, 1e-3, 1.999);
  if (c.contains("delassus_drop_tolerance"))
    o.delassus_drop_tolerance =
        r.number(c, "delassus_drop_tolerance", q, 0, 1e-3);
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

DriverConfig read_driver_config(const std::filesystem::path& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path.string() + ": cannot be read");
  json doc;
  try
  {
    doc = json::parse(in);
  }
  catch (const json::parse_error& e)
  {
    throw std::runtime_error(path.string() + ": not valid JSON: " + e.what());
  }
  const Reader r(path);
  DriverConfig c;
  c.mesh = r.string(doc, "mesh", "");
  const json& m = r.at(doc, "material", "");
  c.material = r.string(m, "name", "material.");
  const json& params = r.at(m, "parameters", "material.");
  if (!params.is_object())
    r.fail("material.parameters", "must be a table of numbers");
  for (const auto& [key, value] : params.items())
    c.material_parameters[key] = r.number(params, key, "material.parameters.");
  c.density = r.number(m, "density", "material.", 1e-12);
  c.walls = read_walls(r, doc);
  if (doc.contains("box"))
  {
    const json& b = doc.at("box");
    c.box = Box{r.string(b, "left", "box."), r.string(b, "right", "box."),
                r.string(b, "bottom", "box."), r.string(b, "top", "box.")};
    for (const std::string& name :
         {c.box->left, c.box->right, c.box->bottom, c.box->top})
      try
      {
        wall_index(c.walls, name);
      }
      catch (const std::runtime_error& e)
      {
        r.fail("box", e.what());
      }
  }
  read_stepping(r, doc, c.stepping);
  const json& stop = r.at(doc, "stop", "");
  if (stop.contains("packing_fraction"))
  {
    if (!c.box)
      r.fail("stop.packing_fraction", "needs a box");
    c.stop_packing_fraction = r.number(stop, "packing_fraction", "stop.", 0, 1);
  }
  c.stop_max_time = r.number(stop, "max_time", "stop.", 0);
  const json& out = r.at(doc, "output", "");
  c.output_directory = r.string(out, "directory", "output.");
  c.output_every_steps =
      static_cast<int>(r.number(out, "every_steps", "output.", 1));
  if (out.contains("fields"))
  {
    const json& f = out.at("fields");
    if (f.is_boolean())
      c.fields_every_outputs = f.get<bool>() ? 1 : 0;
    else
      c.fields_every_outputs =
          static_cast<int>(r.number(out, "fields", "output.", 0));
  }
  if (out.contains("state"))
  {
    if (!out.at("state").is_boolean())
      r.fail("output.state", "must be true or false");
    c.write_state = out.at("state").get<bool>();
  }
  if (doc.contains("initial_state"))
    c.initial_state = r.string(doc, "initial_state", "");
  return c;
}

} // namespace softpack::io
