#pragma once

#include "material_config.h"
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <softpack/list_sections.h>
#include <softpack/parameters.h>
#include <string>
#include <vector>
#include <walls/periodic_cell.h>
#include <walls/walls.h>

/// Reading driver.json (docs/contract.md section 4, docs/driver_io.md).
namespace softpack::io
{

/// Everything `softpack-simulate` needs, read from driver.json.
struct DriverConfig
{
  /// The driver.json file (named in error messages)
  std::filesystem::path file;
  /// The run directory: raw/ and fields.* are written there
  std::filesystem::path directory;
  /// Start from this state file (io/state_file.h) instead of rest
  std::optional<std::filesystem::path> initial_state;
  /// The scene stage's record, as given (copied into raw/setup.json)
  nlohmann::json scene;
  /// scene.bodies.mesh: body b = the cells tagged b
  std::filesystem::path mesh;
  /// scene.bodies.species: species index of each body
  std::vector<int> body_species;
  /// scene.box.enabled: Phi is measured inside the walls left, right,
  /// bottom and top
  bool box = false;
  /// scene.model.dimension: 2 (plane strain, triangles) or 3 (tetrahedra);
  /// a scene record without it (written before 3D scenes) is 2D
  int dimension = 2;
  /// scene.box.height: in 3D the box's edge along z, between the base
  /// z = 0 and the lid (> 0 with a box); 0 in 2D
  double box_height = 0;
  /// The periodic cell (cell.enabled; docs/periodic_cell.md), in place of
  /// a box and walls
  std::optional<dynamics::PeriodicCell> cell;
  /// Its drive from [cell], and each stage's (cell.*; the same count as
  /// stages, empty without a cell)
  dynamics::CellDrive cell_drive;
  std::vector<dynamics::CellDrive> stage_cells;
  /// The walls, in driver.json's order, normals normalised (read by the
  /// reader generated from the schema's [walls]; raw/setup.json records
  /// them as read)
  std::vector<dynamics::Wall> walls;
  /// stop, contact, time, damping, output, material (generated from
  /// schema/parameters.toml)
  parameters::Parameters parameters;
  /// The bodies' materials (material, materials and each species'
  /// material) and the contacts' friction coefficients (contact.friction
  /// and friction): docs/materials.md
  BodyMaterials body_materials;
  dynamics::FrictionTable friction;
  /// driver.json's materials and friction as given (raw/setup.json)
  nlohmann::json materials, friction_pairs;
  /// Velocity scale of the Newton test: the fastest wall speed (derived
  /// here, not a parameter), over the stages' velocities too, or the
  /// cell's edges' speed when larger
  double velocity_scale = 0;
  /// The loading stages, in order (empty: one stage from walls and stop);
  /// their wall names and strain walls name walls of `walls`
  std::vector<parameters::Stage> stages;
  /// driver.json's stages as given, once read and checked
  /// (raw/setup.json: a run with stages describes its program)
  nlohmann::json stage_program;
};

/// Parse and check a driver.json file: every key required, unknown keys
/// refused, schema_version 2.
/// @throws std::runtime_error naming the file and the key at fault
DriverConfig read_driver_config(const std::filesystem::path& path);

/// Refuse a scene.bodies.species whose length is not the mesh's body count.
/// @throws std::runtime_error naming the file and the key
void check_body_count(const DriverConfig& config, int num_bodies);

/// The fastest wall speed max |velocity|, or 1e-3 m/s when every wall is
/// fixed.
double fastest_wall_speed(const std::vector<dynamics::Wall>& walls);

/// Index of the wall with this name.
/// @throws std::runtime_error if absent
int wall_index(const std::vector<dynamics::Wall>& walls,
               const std::string& name);

/// Refuse a drive with a value of another control than its own: a wall is
/// driven by one of velocity, pressure or force ([walls] and [[stages]]).
/// @throws std::runtime_error naming `file` and `path`
void check_drive(const dynamics::WallDrive& drive, const std::string& file,
                 const std::string& path);

/// Names of the box walls (scene.box.enabled), in the order left, right,
/// bottom, top.
inline const std::vector<std::string> box_wall_names = {"left", "right",
                                                        "bottom", "top"};

} // namespace softpack::io
