#include "body_materials.h"

#include <algorithm>
#include <dolfinx/mesh/MeshTags.h>
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

std::shared_ptr<fem::Form<double>>
restrict_to_cells(const fem::Form<double>& a,
                  const std::vector<std::int32_t>& cells)
{
  using Kernel =
      std::function<void(double*, const double*, const double*, const double*,
                         const int*, const std::uint8_t*)>;
  if (!a.integral_ids(fem::IntegralType::exterior_facet).empty() ||
      !a.integral_ids(fem::IntegralType::interior_facet).empty())
    throw std::logic_error("restrict_to_cells: facet integrals");
  const Kernel kernel = a.kernel(fem::IntegralType::cell, cell_integral_id(a));
  const std::shared_ptr<const mesh::Mesh> mesh = a.mesh();
  // The tags are read by the Form's constructor, not kept.
  const mesh::MeshTags<int> tags(mesh, mesh->topology().dim(), cells,
                                 std::vector<int>(cells.size(), 0));
  std::map<fem::IntegralType, std::pair<std::vector<std::pair<int, Kernel>>,
                                        const mesh::MeshTags<int>*>>
      integrals;
  integrals[fem::IntegralType::cell] = {{{0, kernel}}, &tags};
  return std::make_shared<fem::Form<double>>(
      a.function_spaces(), integrals, a.coefficients(), a.constants(),
      a.needs_facet_permutations(), mesh);
}

} // namespace softpack::bodies
