#pragma once

#include <bodies/body_material.h>
#include <detection/friction_table.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

/// driver.json's materials and friction pairs (docs/materials.md).
namespace softpack::io
{
struct DriverConfig;

/// The bodies' materials: every material a species uses, and each body's.
struct BodyMaterials
{
  /// materials[0] is driver.json's `material`, materials[k] (k >= 1) its
  /// `materials[k - 1]`
  std::vector<bodies::BodyMaterial> materials;
  /// Index in `materials` of each body's material (its species')
  std::vector<int> body_material;
};

/// Make the bodies' materials from `material` (config.parameters),
/// `materials` (each {name, law, density, rigid, parameters}) and each
/// species' `scene.species[k].material` ("": the default `material`, else a
/// name of `materials`).
/// @param[in] doc driver.json
/// @param[in] config Its parameters, body species (scene.bodies.species) and
/// file name
/// @throws std::runtime_error naming the file and the key at fault
BodyMaterials read_body_materials(const nlohmann::json& doc,
                                  const DriverConfig& config);

/// Read `friction` ([{species, against, coefficient, law, cohesion,
/// cohesive_distance, tensile_strength, shear_strength, bonding_distance}]:
/// a species name against a species name, a wall name or "walls") into the
/// table of the coefficients, cohesions and bonds of those pairs (every
/// other pair has contact.friction, no cohesion and no bond).
/// @throws std::runtime_error naming the file and the key at fault
dynamics::FrictionTable read_friction_table(const nlohmann::json& doc,
                                            const DriverConfig& config);

} // namespace softpack::io
