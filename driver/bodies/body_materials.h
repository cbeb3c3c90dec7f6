#pragma once

#include "body_material.h"
#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/Form.h>
#include <map>
#include <material_registry.h>
#include <memory>
#include <string>
#include <vector>

namespace softpack::bodies
{

/// The constants of one material, as its forms name them.
using ConstantMap =
    std::map<std::string,
             std::shared_ptr<const dolfinx::fem::Constant<double>>>;

/// Every constant the law declares, and nothing else, plus the density
/// "rho" of the mass forms.
/// @throws std::invalid_argument naming `material.name`.parameters.KEY
ConstantMap material_constants(const BodyMaterial& material);

/// The one cell integral of a form (default or restricted) and its id.
int cell_integral_id(const dolfinx::fem::Form<double>& a);

} // namespace softpack::bodies
