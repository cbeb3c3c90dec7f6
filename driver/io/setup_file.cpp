#include "setup_file.h"

#include <fstream>
#include <stdexcept>

namespace softpack::io
{
namespace
{
using json = nlohmann::json;

/// driver.json's walls as read (normals normalised), each its name and the
/// schema's [walls] keys.
json walls_json(const DriverConfig& config)
{
  json out = json::array();
  for (std::size_t i = 0; i < config.walls.size(); ++i)
  {
    json wall = {{"name", config.walls[i].name}};
    wall.update(parameters::to_json(config.walls[i]));
    out.push_back(wall);
  }
  return out;
}

json bodies_json(const DriverConfig& config, const bodies::BodySet& bodies)
{
  json area = json::array(), nodes = json::array();
  // From the cells' bodies: a rank keeps its own bodies' cell lists only
  std::vector<long> triangles(bodies.num_bodies(), 0);
  for (int b : bodies.cell_body())
    ++triangles[b];
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    area.push_back(bodies.body(b).reference_area);
    nodes.push_back(bodies.body(b).nodes.size());
  }
  // 2D: "triangles" as before 3D bodies; 3D: "tetrahedra" and the volumes
  // under "reference_area" (the one name of a body's reference measure)
  return {{"count", bodies.num_bodies()},
          {"species", config.body_species},
          {"reference_area", area},
          {"nodes", nodes},
          {bodies.dim() == 3 ? "tetrahedra" : "triangles", triangles}};
}

json units(int dim)
{
  if (dim == 3)
    return {{"length", "m"},
            {"time", "s"},
            {"mass", "kg"},
            {"force", "N"},
            {"energy", "J"},
            {"stress", "Pa"},
            {"note", "3D model: tetrahedral solids; reference_area is "
                     "each body's volume (m^3)"}};
  return {{"length", "m"},
          {"time", "s"},
          {"mass", "kg"},
          {"force", "N/m"},
          {"energy", "J/m"},
          {"stress", "Pa"},
          {"note", "2D model: per unit length along z; multiply by "
                   "scene.model.thickness"}};
}
} // namespace

json setup_json(const DriverConfig& config, const bodies::BodySet& bodies)
{
  const parameters::Parameters& p = config.parameters;
  return {{"schema_version", parameters::schema_version},
          {"units", units(bodies.dim())},
          {"scene", config.scene},
          {"material", parameters::to_json(p.material)},
          {"materials", config.materials},
          {"friction", config.friction_pairs},
          {"walls", walls_json(config)},
          {"stages", config.stage_program},
          {"parameters",
           {{"stop", parameters::to_json(p.stop)},
            {"contact", parameters::to_json(p.contact)},
            {"time", parameters::to_json(p.time)},
            {"damping", parameters::to_json(p.damping)},
            {"gravity", parameters::to_json(p.gravity)},
            {"output", parameters::to_json(p.output)},
            {"parallel", parameters::to_json(p.parallel)},
            {"cell", parameters::to_json(p.cell)}}},
          {"initial_state", config.initial_state
                                ? json(config.initial_state->string())
                                : json(nullptr)},
          {"bodies", bodies_json(config, bodies)}};
}

void write_setup(const std::filesystem::path& raw_directory,
                 const nlohmann::json& setup)
{
  std::filesystem::create_directories(raw_directory);
  const std::filesystem::path tmp = raw_directory / ".setup.json";
  {
    std::ofstream out(tmp);
    out << setup.dump(2) << '\n';
    if (!out)
      throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, raw_directory / "setup.json");
}

} // namespace softpack::io
