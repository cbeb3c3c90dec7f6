#include "stress_average.h"

#include "body_assembly.h"
#include <stdexcept>

namespace softpack::bodies
{

std::vector<CauchyIntegral> cauchy_integrals(const BodySet& bodies)
{
  if (bodies.dim() != 2)
    throw std::invalid_argument("cauchy_integrals: plane-strain (2D) bodies "
                                "only; these are 3D");
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  std::vector<CauchyIntegral> out(bodies.num_bodies(), {0, 0, 0, 0});
  for (const int b : bodies.local_bodies())
  {
    for (std::int32_t n : bodies.body(b).nodes)
    {
      const double x = X[2 * n] + u[2 * n], y = X[2 * n + 1] + u[2 * n + 1];
      const double fx = f[2 * n], fy = f[2 * n + 1];
      out[b][0] += fx * x;
      out[b][1] += fy * y;
      out[b][2] += fx * y;
      out[b][3] += fy * x;
    }
  }
  return out;
}

std::vector<CauchyIntegral3D> cauchy_integrals_3d(const BodySet& bodies)
{
  if (bodies.dim() != 3)
    throw std::invalid_argument("cauchy_integrals_3d: 3D bodies only");
  // (i, j) of each component: sum_n f_i x_j
  constexpr int ij[9][2] = {{0, 0}, {1, 1}, {0, 1}, {1, 0}, {2, 2},
                            {0, 2}, {2, 0}, {1, 2}, {2, 1}};
  std::vector<double> f(bodies.num_dofs());
  bodies.internal_force(f);
  const std::span<const double> X = bodies.reference_coordinates();
  const std::span<const double> u = bodies.displacement();
  std::vector<CauchyIntegral3D> out(bodies.num_bodies()); // zeros
  for (const int b : bodies.local_bodies())
    for (std::int32_t n : bodies.body(b).nodes)
      for (int k = 0; k < 9; ++k)
      {
        const int i = ij[k][0], j = ij[k][1];
        out[b][k] += f[3 * n + i] * (X[3 * n + j] + u[3 * n + j]);
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
  const CellKernel kernel{_kernel, _constants};
  const std::span<const double> x = _bodies.reference_coordinates(),
                                u = _bodies.displacement();
  std::vector<CauchyIntegral> out(_bodies.num_bodies(), {0, 0, 0, 0});
  for (int b = 0; b < _bodies.num_bodies(); ++b)
    for_each_cell<4>(_bodies.body(b), kernel, x, u,
                     [&](std::size_t, const double* integral)
                     {
                       for (int k = 0; k < 4; ++k)
                         out[b][k] += integral[k];
                     });
  return out;
}

} // namespace softpack::bodies
