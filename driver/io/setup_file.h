#pragma once

#include "driver_config.h"
#include <bodies/BodySet.h>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace softpack::io
{

/// The run's description for every later stage, raw/setup.json
/// (docs/contract.md section 5): schema_version, units, scene and material
/// (as driver.json gave them), the walls at t = 0, the loading stages (each
/// its name, wall drives and stop keys, as driver.json gave them; empty
/// without stages), the parameters of each driver section, initial_state,
/// and per body its species, reference area (from the boundary polygon;
/// 3D: the volume from the boundary faces), node and triangle (3D:
/// tetrahedron) counts; the units of the dimension (per unit length in
/// 2D).
nlohmann::json setup_json(const DriverConfig& config,
                          const bodies::BodySet& bodies);

/// Write `setup` as `raw_directory/setup.json` atomically (temporary file,
/// then rename), so that a reader never sees half a file.
void write_setup(const std::filesystem::path& raw_directory,
                 const nlohmann::json& setup);

} // namespace softpack::io
