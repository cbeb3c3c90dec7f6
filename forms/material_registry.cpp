#include "material_registry.h"
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

std::vector<std::string> material_parameters(const MaterialForms& m)
{
  const char** names = m.residual->constant_name_map();
  return std::vector<std::string>(names, names + m.residual->num_constants);
}

} // namespace softpack::forms
