#include "stress_average.h"

#include <dolfinx/fem/DofMap.h>
#include <dolfinx/mesh/Mesh.h>
#include <stdexcept>

namespace softpack::bodies
{
using namespace dolfinx;

std::vector<CauchyIntegral> cauchy_integrals(const BodySet& bodies)
{
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u =
      bodies.displacement_function()->x()->array();
  std::vector<CauchyIntegral> out(bodies.num_bodies(), {0, 0, 0, 0});
  for (int b = 0; b < bodies.num_bodies(); ++b)
    for (std::int32_t n : bodies.body(b).nodes)
    {
      const double x = X[2 * n] + u[2 * n], y = X[2 * n + 1] + u[2 * n + 1];
      const double fx = f[2 * n], fy = f[2 * n + 1];
      out[b][0] += fx * x;
      out[b][1] += fy * y;
      out[b][2] += fx * y;
      out[b][3] += fy * x;
    }
  return out;
}

CauchyIntegralForm::CauchyIntegralForm(
    const BodySet& bodies, const forms::MaterialForms& law,
    const std::map<std::string, double>& parameters)
    : _bodies(bodies)
{
  const ufcx_form& form = *law.cauchy_integral;
  if (form.num_integrals(ufcx_integral_type::cell) != 1 ||
      form.integral_ids(ufcx_integral_type::cell)[0] != -1 ||
      form.num_integrals(ufcx_integral_type::exterior_facet) != 0 ||
      form.num_coefficients != 1 || form.rank != 1)
    throw std::invalid_argument(
        std::string("the cauchy_integral form of law '") + law.name +
        "' is not one cell integral with one coefficient (u)");
  _kernel =
      form.integrals(ufcx_integral_type::cell)[0]->tabulate_tensor_float64;
  const char** names = form.constant_name_map();
  for (int k = 0; k < form.num_constants; ++k)
  {
    auto it = parameters.find(names[k]);
    if (it == parameters.end())
      throw std::invalid_argument(std::string("material.parameters.") +
                                  names[k] + ": missing (law '" + law.name +
                                  "')");
    _constants.push_back(it->second);
  }
}

std::vector<CauchyIntegral> CauchyIntegralForm::evaluate() const
{
  const fem::Function<double>& u_function = *_bodies.displacement_function();
  const fem::DofMap& dofmap = *u_function.function_space()->dofmap();
  const mesh::Geometry& geometry = _bodies.mesh()->geometry();
  const graph::AdjacencyList<std::int32_t>& x_dofmap = geometry.dofmap();
  const std::span<const double> x_g = geometry.x();
  const std::span<const double> u = u_function.x()->array();
  std::vector<CauchyIntegral> out(_bodies.num_bodies(), {0, 0, 0, 0});
  double coordinates[9], w[6], integral[4];
  for (int b = 0; b < _bodies.num_bodies(); ++b)
    for (std::int32_t c : _bodies.body(b).cells)
    {
      const auto x_dofs = x_dofmap.links(c);
      const auto dofs = dofmap.cell_dofs(c);
      for (int i = 0; i < 3; ++i)
      {
        for (int k = 0; k < 3; ++k)
          coordinates[3 * i + k] = x_g[3 * x_dofs[i] + k];
        for (int k = 0; k < 2; ++k)
          w[2 * i + k] = u[2 * dofs[i] + k];
      }
      std::fill(integral, integral + 4, 0.0);
      _kernel(integral, w, _constants.data(), coordinates, nullptr, nullptr);
      for (int k = 0; k < 4; ++k)
        out[b][k] += integral[k];
    }
  return out;
}

} // namespace softpack::bodies
