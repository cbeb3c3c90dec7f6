#include "parallel_residual.h"

#include <dolfinx/fem/utils.h>

namespace softpack::bodies
{
using namespace dolfinx;

ParallelResidual::ParallelResidual(
    const fem::Form<double>& L, std::shared_ptr<const fem::Function<double>> u,
    const std::vector<Body>& bodies)
    : _L(L), _u(std::move(u))
{
  const std::vector<int> ids = L.integral_ids(fem::IntegralType::cell);
  const auto& V = *L.function_spaces().at(0);
  const auto& mesh = *L.mesh();
  std::size_t num_cells = 0;
  for (const Body& body : bodies)
    num_cells += body.cells.size();
  _supported = L.rank() == 1 && ids.size() == 1 && ids[0] == -1 &&
               L.integral_ids(fem::IntegralType::exterior_facet).empty() &&
               L.integral_ids(fem::IntegralType::interior_facet).empty() &&
               L.coefficients().size() == 1 && L.coefficients()[0] == _u &&
               _u->function_space()->dofmap() == V.dofmap() &&
               !V.element()->needs_dof_transformations() &&
               V.dofmap()->bs() == 2 && V.dofmap()->cell_dofs(0).size() == 3 &&
               mesh.geometry().dofmap().num_links(0) == 3 &&
               L.cell_domains(-1).size() == num_cells;
}

void ParallelResidual::assemble(std::span<double> b,
                                const std::vector<Body>& bodies) const
{
  const auto& kernel = _L.kernel(fem::IntegralType::cell, -1);
  const std::vector<double> constants = fem::pack_constants(_L);
  const fem::DofMap& dofmap = *_L.function_spaces()[0]->dofmap();
  const int bs = dofmap.bs();
  const graph::AdjacencyList<std::int32_t>& x_dofmap =
      _L.mesh()->geometry().dofmap();
  const std::span<const double> x_g = _L.mesh()->geometry().x();
  const std::span<const double> u = _u->x()->array();
  const int nb = static_cast<int>(bodies.size());

#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int body = 0; body < nb; ++body)
  {
    double coordinates[9], w[6], be[6];
    for (std::int32_t c : bodies[body].cells)
    {
      const auto x_dofs = x_dofmap.links(c);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          coordinates[3 * i + k] = x_g[3 * x_dofs[i] + k];
      const auto dofs = dofmap.cell_dofs(c);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < bs; ++k)
        {
          w[bs * i + k] = u[bs * dofs[i] + k];
          be[bs * i + k] = 0;
        }
      kernel(be, w, constants.data(), coordinates, nullptr, nullptr);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < bs; ++k)
          b[bs * dofs[i] + k] += be[bs * i + k];
    }
  }
}

} // namespace softpack::bodies
