#pragma once

#include <map>
#include <material_registry.h>
#include <string>

namespace softpack::bodies
{

/// One material of a BodySet: a compiled law, its parameters, its density.
struct BodyMaterial
{
  /// The compiled law (forms/material_registry.h)
  const forms::MaterialForms* law = nullptr;
  /// Value of every constant the law declares
  std::map<std::string, double> parameters;
  /// Mass density (kg per unit reference volume)
  double density = 0;
  /// Bodies of this material move rigidly (dynamics/rigid_bodies.h); the
  /// law's forms are still assembled on them and vanish (to round-off) at
  /// their exactly rigid motions
  bool rigid = false;
  /// Where it was given, for messages: "material", "materials[0]", ...
  std::string name = "material";
};

} // namespace softpack::bodies
