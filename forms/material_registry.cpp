#include "material_registry.h"
#include <algorithm>
#include <stdexcept>

namespace softpack::forms
{

std::vector<std::string> material_names()
{
  std::vector<std::string> names;
  for (const MaterialForms& m : material_table())
    names.emplace_back(m.name);
  return names;
}

const MaterialForms& find_material(std::string_view name)
{
  for (const MaterialForms& m : material_table())
    if (name == m.name)
      return m;
  std::string allowed;
  for (const std::string& n : material_names())
    allowed += (allowed.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown material '" + std::string(name) +
                              "' (registered: " + allowed + ")");
}

const MaterialForms& in_dimension(const MaterialForms& law, int dimension)
{
  if (dimension == law.dimension)
    return law;
  if (dimension == 3 && law.solid)
    return *law.solid;
  if (dimension == 2 && law.dimension == 3)
    return find_material(law.name);
  if (dimension == 3)
    throw std::invalid_argument(
        std::string("law '") + law.name +
        "' is plane strain only: forms/materials/" + law.name +
        ".py does not declare dimensions = (2, 3), so it has no 3D forms");
  throw std::invalid_argument("dimension " + std::to_string(dimension) +
                              " (allowed: 2, 3)");
}

std::vector<std::string> material_parameters(const MaterialForms& m)
{
  const char** names = m.residual->constant_name_map();
  std::vector<std::string> out(names, names + m.residual->num_constants);
  if (m.internal_update)
  {
    const char** more = m.internal_update->constant_name_map();
    for (int k = 0; k < m.internal_update->num_constants; ++k)
      if (std::string_view(more[k]) != "time_step" &&
          std::find(out.begin(), out.end(), more[k]) == out.end())
        out.emplace_back(more[k]);
  }
  if (m.nodal_volumetric)
    out.emplace_back(m.nodal_volumetric);
  return out;
}

int internal_size(const MaterialForms& m)
{
  // the coefficient `internal` (the update's test space may add the
  // dissipation)
  return m.internal_update
             ? m.internal_update->finite_elements[2]->space_dimension
             : 0;
}

} // namespace softpack::forms
