#include "body_assembly.h"

#include "body_materials.h"
#include <cmath>
#include <dolfinx/fem/utils.h>
#include <stdexcept>
#include <type_traits>

namespace softpack::bodies
{
using namespace dolfinx;

namespace
{
/// Why a form is not of the kind the loops handle (empty: it is)
std::string unsupported(const fem::Form<double>& a, int rank,
                        const std::shared_ptr<const fem::Function<double>>& u)
{
  const int dim = u->function_space()->mesh()->geometry().dim();
  if (a.rank() != rank)
    return "rank " + std::to_string(a.rank()) + ", not " + std::to_string(rank);
  if (a.integral_ids(fem::IntegralType::cell).size() != 1 ||
      !a.integral_ids(fem::IntegralType::exterior_facet).empty() ||
      !a.integral_ids(fem::IntegralType::interior_facet).empty())
    return "not one cell integral";
  if (a.coefficients().size() > 1 ||
      (a.coefficients().size() == 1 && a.coefficients()[0] != u))
    return "a coefficient other than the displacement";
  for (const auto& V : a.function_spaces())
    if (V->element()->needs_dof_transformations() || V->dofmap()->bs() != dim ||
        V->dofmap()->cell_dofs(0).size() != std::size_t(dim + 1) ||
        V->dofmap() != u->function_space()->dofmap())
      return "a space other than the displacement's (P1 vectors)";
  if (a.mesh()->geometry().dofmap().num_links(0) != dim + 1)
    return "a geometry other than straight triangles or tetrahedra";
  return "";
}

CellKernel cell_kernel(const fem::Form<double>& a, int rank, const char* name,
                       const std::shared_ptr<const fem::Function<double>>& u)
{
  const std::string why = unsupported(a, rank, u);
  if (!why.empty())
    throw std::invalid_argument(std::string("BodyAssembly: the ") + name +
                                " form has " + why +
                                ": the body assembly handles P1 vectors on "
                                "triangles or tetrahedra with the "
                                "displacement as the only coefficient");
  return {a.kernel(fem::IntegralType::cell, cell_integral_id(a)),
          fem::pack_constants(a)};
}

/// The scalar DOFs of a P1 cell in dimension D (D per node)
template <int D> constexpr int cell_dofs = D*(D + 1);

/// Add an element matrix (6x6 in 2D, 12x12 in 3D) into a body's matrix
/// (its lower triangle), in the order of dolfinx's matrix assembler
template <int D>
void add_element(BodyMatrix& A, const CellNodes& cell, const double* Ae)
{
  constexpr int n = cell_dofs<D>;
  for (int i = 0; i <= D; ++i)
    for (int ci = 0; ci < D; ++ci)
      for (int j = 0; j <= D; ++j)
        for (int cj = 0; cj < D; ++cj)
        {
          const int row = D * cell[i] + ci, col = D * cell[j] + cj;
          if (stored_entry(row, col))
            A.coeffRef(row, col) += Ae[(D * i + ci) * n + D * j + cj];
        }
}

/// work(std::integral_constant<int, D>) for D = dim: the dimension a
/// template parameter of the loops from here on
template <typename Work> void with_dimension(int dim, Work&& work)
{
  if (dim == 3)
    work(std::integral_constant<int, 3>{});
  else
    work(std::integral_constant<int, 2>{});
}

/// Whether body b is flagged (all are when `only` is empty)
bool flagged(std::span<const char> only, int b)
{
  return only.empty() || only[b];
}

/// work(k) for each flagged body k, whole bodies to the threads (bodies
/// share no node: no two threads write the same entry)
template <typename Work>
void for_each_body(std::size_t count, std::span<const char> only, Work&& work)
{
  const int nb = static_cast<int>(count);
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int k = 0; k < nb; ++k)
    if (flagged(only, k))
      work(k);
}
} // namespace

BodyAssembly::BodyAssembly(
    const std::vector<BodyForms>& forms, std::vector<int> body_forms,
    const std::shared_ptr<const fem::Function<double>>& u)
    : _body_forms(std::move(body_forms)),
      _dim(u->function_space()->mesh()->geometry().dim()),
      _nodal(_body_forms.size())
{
  for (const BodyForms& f : forms)
  {
    if (f.internal)
    {
      const InternalForms& in = *f.internal;
      _kernels.push_back({in.energy, in.residual, in.tangent,
                          cell_kernel(*f.mass, 2, "mass", u),
                          cell_kernel(*f.lumped_mass, 2, "lumped mass", u),
                          in.update, in.time_step, f.nodal_lambda});
      continue;
    }
    _kernels.push_back({cell_kernel(*f.energy, 0, "energy", u),
                        cell_kernel(*f.residual, 1, "residual", u),
                        cell_kernel(*f.tangent, 2, "tangent", u),
                        cell_kernel(*f.mass, 2, "mass", u),
                        cell_kernel(*f.lumped_mass, 2, "lumped mass", u),
                        {},
                        0,
                        f.nodal_lambda});
  }
}

NodalPatches& BodyAssembly::nodal(int k, const Body& body,
                                  std::span<const double> x) const
{
  std::unique_ptr<NodalPatches>& patches = _nodal[k];
  if (!patches || !patches->fits(body))
    patches = std::make_unique<NodalPatches>(body, x);
  return *patches;
}

void BodyAssembly::cell_energy(std::span<double> per_cell,
                               const std::vector<Body>& bodies,
                               std::span<const double> x,
                               std::span<const double> u,
                               std::span<const char> only) const
{
  for_each_body(
      bodies.size(), only,
      [&](int k)
      {
        const Body& body = bodies[k];
        with_dimension(_dim,
                       [&](auto d)
                       {
                         cells<1, decltype(d)::value>(
                             k, _kernels[_body_forms[k]].energy, bodies, x, u,
                             [&](std::size_t c, const double* e)
                             { per_cell[body.cells[c]] = e[0]; });
                       });
        if (const double lambda = _kernels[_body_forms[k]].nodal_lambda)
          nodal(k, body, x).add_cell_energy(body, x, u, lambda, per_cell);
      });
}

void BodyAssembly::residual(std::span<double> b,
                            const std::vector<Body>& bodies,
                            std::span<const double> x,
                            std::span<const double> u,
                            std::span<const char> only) const
{
  for_each_body(
      bodies.size(), only,
      [&](int k)
      {
        const Body& body = bodies[k];
        with_dimension(_dim,
                       [&](auto dim)
                       {
                         constexpr int D = decltype(dim)::value;
                         cells<cell_dofs<D>, D>(
                             k, _kernels[_body_forms[k]].residual, bodies, x, u,
                             [&](std::size_t c, const double* be)
                             {
                               const CellNodes& cell = body.cell_nodes[c];
                               for (int i = 0; i <= D; ++i)
                                 for (int d = 0; d < D; ++d)
                                   b[D * body.nodes[cell[i]] + d] +=
                                       be[D * i + d];
                             });
                       });
        if (const double lambda = _kernels[_body_forms[k]].nodal_lambda)
          nodal(k, body, x).add_residual(body, x, u, lambda, b);
      });
}

void BodyAssembly::matrices(CellKernel Kernels::*form,
                            std::vector<BodyMatrix>& A,
                            const std::vector<Body>& bodies,
                            std::span<const double> x,
                            std::span<const double> u,
                            std::span<const char> only) const
{
  for_each_body(
      bodies.size(), only,
      [&](int k)
      {
        BodyMatrix& Ak = A[k];
        std::fill_n(Ak.valuePtr(), Ak.nonZeros(), 0.0);
        const Body& body = bodies[k];
        with_dimension(
            _dim,
            [&](auto dim)
            {
              constexpr int D = decltype(dim)::value, n = cell_dofs<D>;
              cells<n * n, D>(k, _kernels[_body_forms[k]].*form, bodies, x, u,
                              [&](std::size_t c, const double* Ae)
                              { add_element<D>(Ak, body.cell_nodes[c], Ae); });
            });
      });
}

void BodyAssembly::tangent(std::vector<BodyMatrix>& K,
                           const std::vector<Body>& bodies,
                           std::span<const double> x, std::span<const double> u,
                           std::span<const char> only) const
{
  matrices(&Kernels::tangent, K, bodies, x, u, only);
  for_each_body(
      bodies.size(), only,
      [&](int k)
      {
        if (const double lambda = _kernels[_body_forms[k]].nodal_lambda)
          nodal(k, bodies[k], x).add_tangent(bodies[k], x, u, lambda, K[k]);
      });
}

void BodyAssembly::mass(std::vector<BodyMatrix>& M,
                        const std::vector<Body>& bodies,
                        std::span<const double> x,
                        std::span<const char> only) const
{
  matrices(&Kernels::mass, M, bodies, x, {}, only);
}

std::vector<Eigen::VectorXd>
BodyAssembly::lumped_mass(const std::vector<Body>& bodies,
                          std::span<const double> x,
                          std::span<const char> only) const
{
  std::vector<Eigen::VectorXd> lumped(bodies.size());
  for_each_body(bodies.size(), only,
                [&](int k)
                {
                  Eigen::VectorXd& m = lumped[k];
                  m = Eigen::VectorXd::Zero(bodies[k].num_dofs());
                  // The diagonal of the form's matrix, summed as its entries
                  // are
                  const Body& body = bodies[k];
                  with_dimension(
                      _dim,
                      [&](auto dim)
                      {
                        constexpr int D = decltype(dim)::value,
                                      n = cell_dofs<D>;
                        for_each_cell<n * n, D>(
                            body, _kernels[_body_forms[k]].lumped_mass, x, {},
                            [&](std::size_t c, const double* Ae)
                            {
                              const CellNodes& cell = body.cell_nodes[c];
                              for (int i = 0; i <= D; ++i)
                                for (int d = 0; d < D; ++d)
                                  m[D * cell[i] + d] +=
                                      Ae[(D * i + d) * n + D * i + d];
                            });
                      });
                });
  return lumped;
}

} // namespace softpack::bodies
