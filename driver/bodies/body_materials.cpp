#include "body_materials.h"

#include <algorithm>
#include <stdexcept>

namespace softpack::bodies
{
using namespace dolfinx;

ConstantMap material_constants(const BodyMaterial& material)
{
  if (!material.law)
    throw std::invalid_argument(material.name + ".law: no law given");
  if (!(material.density > 0))
    throw std::invalid_argument(material.name + ".density must be positive");
  const std::vector<std::string> declared =
      forms::material_parameters(*material.law);
  std::string allowed;
  for (const std::string& d : declared)
    allowed += (allowed.empty() ? "" : ", ") + d;
  auto fail = [&](const std::string& key, const std::string& what)
  {
    throw std::invalid_argument(material.name + ".parameters." + key + ": " +
                                what + " (law '" +
                                std::string(material.law->name) +
                                "' has the parameters " + allowed + ")");
  };
  ConstantMap constants;
  for (const std::string& key : declared)
  {
    auto it = material.parameters.find(key);
    if (it == material.parameters.end())
      fail(key, "missing");
    constants[key] = std::make_shared<fem::Constant<double>>(it->second);
  }
  for (const auto& [key, value] : material.parameters)
    if (std::find(declared.begin(), declared.end(), key) == declared.end())
      fail(key, "unknown parameter");
  constants["rho"] = std::make_shared<fem::Constant<double>>(material.density);
  return constants;
}

int cell_integral_id(const fem::Form<double>& a)
{
  const std::vector<int> ids = a.integral_ids(fem::IntegralType::cell);
  if (ids.size() != 1)
    throw std::logic_error("a material form must have one cell integral");
  return ids[0];
}

} // namespace softpack::bodies
