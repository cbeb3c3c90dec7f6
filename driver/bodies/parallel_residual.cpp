#include "parallel_residual.h"

#include "body_materials.h"
#include <dolfinx/fem/utils.h>

namespace softpack::bodies
{
using namespace dolfinx;

namespace
{
/// Whether one form is of the kind the loop handles.
bool supported_form(const fem::Form<double>& L,
                    const std::shared_ptr<const fem::Function<double>>& u)
{
  const std::vector<int> ids = L.integral_ids(fem::IntegralType::cell);
  const auto& V = *L.function_spaces().at(0);
  const auto& mesh = *L.mesh();
  return L.rank() == 1 && ids.size() == 1 &&
         L.integral_ids(fem::IntegralType::exterior_facet).empty() &&
         L.integral_ids(fem::IntegralType::interior_facet).empty() &&
         L.coefficients().size() == 1 && L.coefficients()[0] == u &&
         u->function_space()->dofmap() == V.dofmap() &&
         !V.element()->needs_dof_transformations() && V.dofmap()->bs() == 2 &&
         V.dofmap()->cell_dofs(0).size() == 3 &&
         mesh.geometry().dofmap().num_links(0) == 3;
}
} // namespace

ParallelResidual::ParallelResidual(
    std::vector<const fem::Form<double>*> L, std::vector<int> body_form,
    std::shared_ptr<const fem::Function<double>> u,
    const std::vector<Body>& bodies)
    : _L(std::move(L)), _body_form(std::move(body_form)), _u(std::move(u))
{
  std::size_t num_cells = 0, covered = 0;
  for (const Body& body : bodies)
    num_cells += body.cells.size();
  _supported = !_L.empty() && _body_form.size() == bodies.size();
  for (const fem::Form<double>* form : _L)
  {
    _supported = _supported && supported_form(*form, _u);
    if (_supported)
      covered += form->cell_domains(cell_integral_id(*form)).size();
  }
  _supported = _supported && covered == num_cells;
}

void ParallelResidual::assemble(std::span<double> b,
                                const std::vector<Body>& bodies,
                                std::span<const char> owned) const
{
  std::vector<std::vector<double>> constants;
  for (const fem::Form<double>* form : _L)
    constants.push_back(fem::pack_constants(*form));
  const fem::DofMap& dofmap = *_L.front()->function_spaces()[0]->dofmap();
  const int bs = dofmap.bs();
  const graph::AdjacencyList<std::int32_t>& x_dofmap =
      _L.front()->mesh()->geometry().dofmap();
  const std::span<const double> x_g = _L.front()->mesh()->geometry().x();
  const std::span<const double> u = _u->x()->array();
  const int nb = static_cast<int>(bodies.size());

#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int body = 0; body < nb; ++body)
  {
    if (!owned.empty() && !owned[body])
      continue;
    const fem::Form<double>& L = *_L[_body_form[body]];
    const auto& kernel = L.kernel(fem::IntegralType::cell, cell_integral_id(L));
    const double* c = constants[_body_form[body]].data();
    double coordinates[9], w[6], be[6];
    for (std::int32_t cell : bodies[body].cells)
    {
      const auto x_dofs = x_dofmap.links(cell);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          coordinates[3 * i + k] = x_g[3 * x_dofs[i] + k];
      const auto dofs = dofmap.cell_dofs(cell);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < bs; ++k)
        {
          w[bs * i + k] = u[bs * dofs[i] + k];
          be[bs * i + k] = 0;
        }
      kernel(be, w, c, coordinates, nullptr, nullptr);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < bs; ++k)
          b[bs * dofs[i] + k] += be[bs * i + k];
    }
  }
}

} // namespace softpack::bodies
