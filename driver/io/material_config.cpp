#include "material_config.h"

#include "driver_config.h"
#include <algorithm>
#include <cmath>
#include <material_registry.h>
#include <stdexcept>

namespace softpack::io
{
namespace
{
using json = nlohmann::json;

[[noreturn]] void fail(const DriverConfig& c, const std::string& key,
                       const std::string& what)
{
  throw std::runtime_error(c.file.string() + ": " + key + ": " + what);
}

/// One material: the generated reader checks law, density and rigid; the
/// law's parameters are checked against the registry by the body set.
bodies::BodyMaterial read_material(const DriverConfig& c, const json& j,
                                   const std::string& key)
{
  if (!j.is_object() || !j.contains("parameters") ||
      !j.at("parameters").is_object())
    fail(c, key + ".parameters", "missing or not a table");
  json keys = j;
  keys.erase("parameters");
  parameters::MaterialsEntry entry;
  parameters::read(keys, entry, c.file.string(), key);
  bodies::BodyMaterial m;
  try
  {
    m.law = &forms::find_material(entry.law);
  }
  catch (const std::invalid_argument& e)
  {
    fail(c, key + ".law", e.what());
  }
  for (const auto& [name, value] : j.at("parameters").items())
  {
    if (!value.is_number())
      fail(c, key + ".parameters." + name, "must be a number");
    m.parameters[name] = value.get<double>();
  }
  m.density = entry.density;
  m.rigid = entry.rigid;
  m.name = key;
  return m;
}
} // namespace

BodyMaterials read_body_materials(const json& doc, const DriverConfig& c)
{
  BodyMaterials out;
  // The default material has the keys of a named one but its name.
  json material = doc.at("material");
  if (!material.is_object() || material.contains("name"))
    fail(c, "material", "must be a table of law, density, rigid, parameters");
  material["name"] = "material";
  out.materials.push_back(read_material(c, material, "material"));
  const json& list = doc.at("materials");
  if (!list.is_array())
    fail(c, "materials", "must be a list (empty: none)");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i)
  {
    const std::string key = "materials[" + std::to_string(i) + "]";
    if (!list[i].is_object() || !list[i].contains("name") ||
        !list[i].at("name").is_string())
      fail(c, key + ".name", "missing or not a string");
    names.push_back(list[i].at("name").get<std::string>());
    out.materials.push_back(read_material(c, list[i], key));
  }
  std::vector<int> species_material;
  const json& species = c.scene.at("species");
  for (std::size_t k = 0; k < species.size(); ++k)
  {
    const std::string key = "scene.species[" + std::to_string(k) + "].material";
    const json& name =
        species[k].contains("material") ? species[k].at("material") : json("");
    if (!name.is_string())
      fail(c, key, "must be a string");
    if (name.get<std::string>().empty())
    {
      species_material.push_back(0);
      continue;
    }
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      fail(c, key, "= " + name.dump() + " names no entry of materials");
    species_material.push_back(1 + static_cast<int>(it - names.begin()));
  }
  for (int s : c.body_species)
    out.body_material.push_back(species_material[s]);
  return out;
}

dynamics::FrictionTable read_friction_table(const json& doc,
                                            const DriverConfig& c)
{
  const json& species = c.scene.at("species");
  const int ns = static_cast<int>(species.size());
  dynamics::FrictionTable table(c.parameters.contact.friction, c.body_species,
                                ns, static_cast<int>(c.walls.size()));
  const json& list = doc.at("friction");
  if (!list.is_array())
    fail(c, "friction", "must be a list (empty: none)");
  // Party names: the species', then the walls'; "walls" is every wall.
  auto parties =
      [&](const std::string& name, const std::string& key, bool walls_allowed)
  {
    std::vector<int> out;
    for (int s = 0; s < ns; ++s)
      if (species[s].value("name", "") == name)
        out.push_back(table.species_party(s));
    for (std::size_t w = 0; walls_allowed && w < c.walls.size(); ++w)
      if (c.walls[w].name == name || name == "walls")
        out.push_back(table.wall_party(static_cast<int>(w)));
    if (out.empty())
      fail(c, key,
           "= \"" + name + "\" is not a species" +
               (walls_allowed ? ", a wall or \"walls\"" : ""));
    return out;
  };
  for (std::size_t i = 0; i < list.size(); ++i)
  {
    const std::string key = "friction[" + std::to_string(i) + "]";
    const json& e = list[i];
    if (!e.is_object() || e.size() != 3 || !e.contains("species") ||
        !e.contains("against") || !e.contains("coefficient") ||
        !e.at("species").is_string() || !e.at("against").is_string() ||
        !e.at("coefficient").is_number())
      fail(c, key,
           "must be {species: name, against: name, coefficient: "
           "number}");
    const double mu = e.at("coefficient").get<double>();
    if (!(mu >= 0) || !std::isfinite(mu))
      fail(c, key + ".coefficient", "must be >= 0");
    for (int a : parties(e.at("species"), key + ".species", false))
      for (int b : parties(e.at("against"), key + ".against", true))
        table.set(a, b, mu);
  }
  return table;
}

} // namespace softpack::io
