// The internal variables of the laws that have them (a viscoelastic law's
// Maxwell branches, forms/materials/viscoelastic_neo_hookean.py): one DG0
// value per cell, read by the law's forms beside the displacement, relaxed
// once per accepted step.
#include "BodySet.h"

#include "body_assembly.h"
#include <cmath>
#include <stdexcept>
#include <string>

namespace softpack::bodies
{

namespace
{
/// The cell kernel of one form of a law with internal variables
CellKernel internal_kernel(const forms::MaterialForms& law,
                           const ufcx_form& form, int rank, const char* what,
                           const std::map<std::string, double>& constants,
                           std::size_t* time_step)
{
  auto fail = [&](const std::string& why)
  {
    throw std::invalid_argument(std::string("law '") + law.name + "': its " +
                                what + " form " + why);
  };
  const char** coefficients = form.coefficient_name_map();
  if (form.rank != rank || form.num_coefficients != 2 ||
      std::string_view(coefficients[0]) != "u" ||
      std::string_view(coefficients[1]) != "internal")
    fail("is not of rank " + std::to_string(rank) +
         " with the coefficients u then internal");
  if (form.num_integrals(ufcx_integral_type::cell) != 1 ||
      form.integral_ids(ufcx_integral_type::cell)[0] != -1 ||
      form.num_integrals(ufcx_integral_type::exterior_facet) != 0 ||
      form.num_integrals(ufcx_integral_type::interior_facet) != 0)
    fail("is not one cell integral");
  const int n = form.finite_elements[rank + 1]->space_dimension;
  if (n > max_internal)
    fail("has " + std::to_string(n) + " internal variables per cell (at most " +
         std::to_string(max_internal) + ")");
  CellKernel kernel{
      form.integrals(ufcx_integral_type::cell)[0]->tabulate_tensor_float64,
      {},
      n};
  const char** names = form.constant_name_map();
  for (int k = 0; k < form.num_constants; ++k)
  {
    if (time_step && std::string_view(names[k]) == "time_step")
    {
      *time_step = kernel.constants.size();
      kernel.constants.push_back(0);
      continue;
    }
    const auto it = constants.find(names[k]);
    if (it == constants.end())
      fail(std::string("reads the constant ") + names[k] +
           ", which is no parameter");
    kernel.constants.push_back(it->second);
  }
  return kernel;
}
} // namespace

InternalForms internal_forms(const forms::MaterialForms& law,
                             const std::map<std::string, double>& constants)
{
  if (!law.internal_update)
    throw std::logic_error(std::string("law '") + law.name +
                           "' has no internal variables");
  InternalForms f;
  f.energy = internal_kernel(law, *law.energy, 0, "energy", constants, nullptr);
  f.residual =
      internal_kernel(law, *law.residual, 1, "residual", constants, nullptr);
  f.tangent =
      internal_kernel(law, *law.tangent, 2, "tangent", constants, nullptr);
  f.update = internal_kernel(law, *law.internal_update, 1, "internal_update",
                             constants, &f.time_step);
  // the relaxed values, then the cell's dissipation over the relaxation
  if (law.internal_update->finite_elements[0]->space_dimension !=
          f.update.internal + 1 ||
      f.update.internal !=
          static_cast<int>(forms::internal_initial(law.name).size()))
    throw std::invalid_argument(
        std::string("law '") + law.name +
        "': internal_update's test space must be its coefficient internal "
        "(of internal_initial's size) and one more entry, the cell's "
        "dissipation");
  return f;
}

void BodyAssembly::relax_internal(std::span<double> internal, double h,
                                  const std::vector<Body>& bodies,
                                  std::span<const double> x,
                                  std::span<const double> u,
                                  std::span<double> dissipated,
                                  std::span<double> f,
                                  std::span<const char> only) const
{
  const int nb = static_cast<int>(bodies.size());
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int k = 0; k < nb; ++k)
  {
    const Kernels& kernels = _kernels[_body_forms[k]];
    const int n = kernels.update.internal;
    if ((!only.empty() && !only[k]) || n == 0)
      continue;
    CellKernel update = kernels.update;
    update.constants[kernels.time_step] = h;
    // Each cell read once for its update (the relaxed values and the
    // cell's dissipation) and its internal force after
    const Body& body = bodies[k];
    if (!f.empty()) // summed from zero, as residual does
      for (const std::int32_t g : body.nodes)
        f[2 * g] = f[2 * g + 1] = 0;
    double coordinates[9] = {}; // z = 0
    double w[6 + max_internal] = {}, relaxed[max_internal + 1], fe[6];
    for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
    {
      const CellNodes& cell = body.cell_nodes[c];
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 2; ++d)
        {
          coordinates[3 * i + d] = x[2 * body.nodes[cell[i]] + d];
          w[2 * i + d] = u[2 * body.nodes[cell[i]] + d];
        }
      double* values = &internal[std::size_t(_stride) * body.cells[c]];
      std::copy_n(values, n, w + 6);
      std::fill_n(relaxed, n + 1, 0.0);
      update.tabulate(relaxed, w, update.constants.data(), coordinates, nullptr,
                      nullptr);
      // The form gives each value integrated over the cell (one point):
      // divided by the cell's reference area.
      const double* p[3];
      for (int i = 0; i < 3; ++i)
        p[i] = &x[2 * body.nodes[cell[i]]];
      const double area =
          0.5 * std::abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                         (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
      for (int i = 0; i < n; ++i)
        values[i] = w[6 + i] = relaxed[i] / area;
      dissipated[body.cells[c]] = relaxed[n];
      if (f.empty())
        continue;
      std::fill_n(fe, 6, 0.0);
      kernels.residual.tabulate(fe, w, kernels.residual.constants.data(),
                                coordinates, nullptr, nullptr);
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 2; ++d)
          f[2 * body.nodes[cell[i]] + d] += fe[2 * i + d];
    }
  }
}

void BodySet::init_internal()
{
  _internal_stride = 0;
  for (const BodyMaterial& m : _materials)
    _internal_stride = std::max(_internal_stride, forms::internal_size(*m.law));
  _internal.assign(_cell_body.size() * _internal_stride, 0.0);
  for (std::size_t c = 0; c < _cell_body.size(); ++c)
  {
    const std::span<const double> initial = forms::internal_initial(
        _materials[_body_material[_cell_body[c]]].law->name);
    std::copy(initial.begin(), initial.end(),
              _internal.begin() + c * _internal_stride);
  }
}

void BodySet::set_internal_variables(std::span<const double> values)
{
  if (values.size() != _internal.size())
    throw std::invalid_argument(
        "BodySet::set_internal_variables: " + std::to_string(values.size()) +
        " values for " + std::to_string(_internal.size()) + " (" +
        std::to_string(_cell_body.size()) + " cells of " +
        std::to_string(_internal_stride) + ")");
  std::copy(values.begin(), values.end(), _internal.begin());
}

double BodySet::update_internal_variables(double h, std::span<double> f)
{
  if (_internal_stride == 0)
    return 0;
  if (!f.empty() && f.size() != num_dofs())
    throw std::invalid_argument("update_internal_variables: wrong force "
                                "vector size");
  std::vector<char> flagged(_bodies.size(), 0);
  for (const int b : _local)
    flagged[b] = _assembly->has_internal(b);
  std::vector<double> dissipated(_cell_body.size(), 0.0);
  _assembly->relax_internal(_internal, h, _bodies, _reference_x, _u, dissipated,
                            f, flagged);
  // In body and cell order: the same sum on every run
  double total = 0;
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (flagged[b])
      for (const std::int32_t c : _bodies[b].cells)
        total += dissipated[c];
  return total;
}

std::vector<double> pick_cells(std::span<const double> values, int stride,
                               std::span<const int> cell_body,
                               std::span<const char> flagged)
{
  std::vector<double> out;
  for (std::size_t c = 0; c < cell_body.size(); ++c)
    if (flagged[cell_body[c]])
      out.insert(out.end(), values.begin() + c * stride,
                 values.begin() + (c + 1) * stride);
  return out;
}

std::size_t place_cells(std::span<double> values, int stride,
                        std::span<const int> cell_body,
                        std::span<const char> flagged,
                        std::span<const double> in)
{
  std::size_t k = 0;
  for (std::size_t c = 0; c < cell_body.size(); ++c)
    if (flagged[cell_body[c]])
    {
      if (k + stride > in.size())
        throw std::invalid_argument(
            "place_cells: " + std::to_string(in.size()) +
            " values, the flagged bodies' cells have more");
      std::copy_n(in.begin() + k, stride, values.begin() + c * stride);
      k += stride;
    }
  return k;
}

} // namespace softpack::bodies
