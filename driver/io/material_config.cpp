#include "material_config.h"

#include "driver_config.h"
#include <algorithm>
#include <cmath>
#include <material_registry.h>
#include <softpack/list_sections.h>
#include <stdexcept>
#include <utility>

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

/// One material: the generated reader checked its keys; its law is looked
/// up in the registry here, its parameters checked against the law's by
/// the body set.
bodies::BodyMaterial make_material(const DriverConfig& c,
                                   const std::string& law, double density,
                                   bool rigid,
                                   const std::map<std::string, double>& values,
                                   const std::string& key)
{
  bodies::BodyMaterial m;
  try
  {
    m.law = &forms::find_material(law);
  }
  catch (const std::invalid_argument& e)
  {
    fail(c, key + ".law", e.what());
  }
  m.parameters = values;
  m.density = density;
  m.rigid = rigid;
  m.name = key;
  return m;
}
} // namespace

BodyMaterials read_body_materials(const json& doc, const DriverConfig& c)
{
  BodyMaterials out;
  const parameters::Material& first = c.parameters.material;
  out.materials.push_back(make_material(
      c, first.law, first.density, first.rigid, first.parameters, "material"));
  std::vector<parameters::MaterialsEntry> named;
  parameters::read(doc.at("materials"), named, c.file.string());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < named.size(); ++i)
  {
    const parameters::MaterialsEntry& e = named[i];
    names.push_back(e.name);
    out.materials.push_back(
        make_material(c, e.law, e.density, e.rigid, e.parameters,
                      "materials[" + std::to_string(i) + "]"));
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

namespace
{
/// A pair's cohesion and bond: its law's rule (scene/species.py check_law)
/// checked once more here, where driver.json is read
std::pair<dynamics::Cohesion, dynamics::Bond>
pair_law(const DriverConfig& c, const std::string& key,
         const parameters::FrictionPair& e)
{
  const bool cohesive = e.law == "cohesive", bonded = e.law == "bonded";
  if (!cohesive && (e.cohesion != 0 || e.cohesive_distance != 0))
    fail(c, key,
         "law \"" + e.law +
             "\" with a cohesion or cohesive_distance (only law "
             "\"cohesive\" has them)");
  if (!bonded && (e.tensile_strength != 0 || e.shear_strength != 0 ||
                  e.bonding_distance != 0))
    fail(c, key,
         "law \"" + e.law +
             "\" with a tensile_strength, shear_strength or "
             "bonding_distance (only law \"bonded\" has them)");
  if (cohesive && !(e.cohesion > 0))
    fail(c, key + ".cohesion", "must be > 0 for law \"cohesive\"");
  if (bonded && !(e.tensile_strength > 0))
    fail(c, key + ".tensile_strength", "must be > 0 for law \"bonded\"");
  if (bonded && !(e.shear_strength > 0))
    fail(c, key + ".shear_strength", "must be > 0 for law \"bonded\"");
  if (cohesive)
    return {{e.cohesion, e.cohesive_distance}, {}};
  if (bonded)
    return {{}, {e.tensile_strength, e.shear_strength, e.bonding_distance}};
  return {};
}
} // namespace

dynamics::FrictionTable read_friction_table(const json& doc,
                                            const DriverConfig& c)
{
  const json& species = c.scene.at("species");
  const int ns = static_cast<int>(species.size());
  // Wall parties: driver.json's walls, then a 3D box's base and lid (in
  // the order of simulation::box_walls_3d)
  std::vector<std::string> walls;
  for (const dynamics::Wall& w : c.walls)
    walls.push_back(w.name);
  if (c.dimension == 3 && c.box)
    walls.insert(walls.end(), {"base", "lid"});
  dynamics::FrictionTable table(c.body_species, ns,
                                static_cast<int>(walls.size()));
  std::vector<parameters::FrictionPair> pairs;
  parameters::read(doc.at("friction"), pairs, c.file.string());
  // Party names: the species', then the walls'; "walls" is every wall.
  auto parties =
      [&](const std::string& name, const std::string& key, bool walls_allowed)
  {
    std::vector<int> out;
    for (int s = 0; s < ns; ++s)
      if (species[s].value("name", "") == name)
        out.push_back(table.species_party(s));
    for (std::size_t w = 0; walls_allowed && w < walls.size(); ++w)
      if (walls[w] == name || name == "walls")
        out.push_back(table.wall_party(static_cast<int>(w)));
    if (out.empty())
      fail(c, key,
           "= \"" + name + "\" is not a species" +
               (walls_allowed ? ", a wall or \"walls\"" : ""));
    return out;
  };
  for (std::size_t i = 0; i < pairs.size(); ++i)
  {
    const std::string key = "friction[" + std::to_string(i) + "]";
    const parameters::FrictionPair& e = pairs[i];
    const auto [cohesion, bond] = pair_law(c, key, e);
    for (int a : parties(e.species, key + ".species", false))
      for (int b : parties(e.against, key + ".against", true))
        table.set(a, b, e.coefficient, cohesion, bond);
  }
  return table;
}

} // namespace softpack::io
