// The bodies' matrices: one sparse pattern per body, the tangent assembled
// into it, and the masses a rank keeps (its own bodies and every rigid one).
#include "BodySet.h"

#include "body_materials.h"
#include <algorithm>
#include <dolfinx/fem/assembler.h>
#include <stdexcept>

namespace softpack::bodies
{
using namespace dolfinx;

std::vector<BodyMatrix>
BodySet::create_matrices(std::span<const char> only) const
{
  const fem::DofMap& dofmap = *_V->dofmap();
  std::vector<BodyMatrix> matrices;
  matrices.reserve(_bodies.size());
  for (std::size_t b = 0; b < _bodies.size(); ++b)
  {
    const Body& body = _bodies[b];
    if (!only.empty() && !only[b])
    {
      matrices.emplace_back(body.num_dofs(), body.num_dofs());
      continue;
    }
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(36 * body.cells.size());
    for (std::int32_t c : body.cells)
      for (std::int32_t ni : dofmap.cell_dofs(c))
        for (std::int32_t nj : dofmap.cell_dofs(c))
          for (int ci = 0; ci < 2; ++ci)
            for (int cj = 0; cj < 2; ++cj)
            {
              const int row = 2 * _node_local[ni] + ci,
                        col = 2 * _node_local[nj] + cj;
              if (stored_entry(row, col))
                pattern.emplace_back(row, col, 0.0);
            }
    // Built in place: Eigen 3.4's sparse matrix has no move constructor,
    // so a push_back would copy it.
    BodyMatrix& A = matrices.emplace_back(body.num_dofs(), body.num_dofs());
    A.setFromTriplets(pattern.begin(), pattern.end());
    A.makeCompressed();
  }
  return matrices;
}

namespace
{
/// Zero the values of per-body matrices, keeping their patterns
void zero(std::vector<BodyMatrix>& matrices)
{
  for (BodyMatrix& A : matrices)
    std::fill_n(A.valuePtr(), A.nonZeros(), 0.0);
}

/// Add a bilinear form into per-body matrices holding its pattern.
void assemble_by_body(const fem::Form<double>& a,
                      const std::vector<std::int32_t>& node_body,
                      const std::vector<std::int32_t>& node_local,
                      std::vector<BodyMatrix>& matrices)
{
  auto add = [&](std::span<const std::int32_t> rows,
                 std::span<const std::int32_t> cols,
                 std::span<const double> values)
  {
    BodyMatrix& A = matrices[node_body[rows[0]]];
    const std::size_t ncols = 2 * cols.size();
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int ci = 0; ci < 2; ++ci)
        for (std::size_t j = 0; j < cols.size(); ++j)
          for (int cj = 0; cj < 2; ++cj)
          {
            const int row = 2 * node_local[rows[i]] + ci,
                      col = 2 * node_local[cols[j]] + cj;
            if (stored_entry(row, col))
              A.coeffRef(row, col) += values[(2 * i + ci) * ncols + 2 * j + cj];
          }
    return 0;
  };
  fem::assemble_matrix(add, a, {});
}
} // namespace

void BodySet::tangent(std::vector<BodyMatrix>& K) const
{
  zero(K);
  for (const MaterialForms& f : _forms)
    assemble_by_body(*f.tangent, _node_body, _node_local, K);
}

void BodySet::build_mass()
{
  _mass = create_matrices();
  std::vector<BodyMatrix> lumped = create_matrices();
  zero(_mass);
  zero(lumped);
  for (const MaterialForms& f : _forms)
  {
    assemble_by_body(*f.mass, _node_body, _node_local, _mass);
    assemble_by_body(*f.lumped_mass, _node_body, _node_local, lumped);
  }
  _lumped_mass.clear();
  for (const BodyMatrix& A : lumped)
    _lumped_mass.push_back(A.diagonal());
}

void BodySet::set_owned(std::vector<char> owned)
{
  if (owned.size() != _bodies.size())
    throw std::invalid_argument(
        "BodySet::set_owned: " + std::to_string(owned.size()) + " flags for " +
        std::to_string(_bodies.size()) + " bodies");
  // The tangent is the expensive assembly: its forms run over the owned
  // bodies' cells only (each material's over its own owned bodies).
  for (MaterialForms& f : _forms)
  {
    if (!f.all_tangent)
      f.all_tangent = f.tangent;
    f.tangent = restrict_to_cells(*f.all_tangent, cells_of(owned, f));
  }
  keep_masses(kept_masses(owned));
  _owned = std::move(owned);
}

std::vector<char> BodySet::kept_masses(std::span<const char> owned) const
{
  std::vector<char> kept(_bodies.size(), 1);
  if (!owned.empty())
    for (std::size_t b = 0; b < kept.size(); ++b)
      kept[b] = owned[b] || rigid(static_cast<int>(b));
  return kept;
}

std::vector<std::int32_t> BodySet::cells_of(std::span<const char> flags,
                                            const MaterialForms& f) const
{
  std::vector<std::int32_t> cells;
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (flags[b] && (_forms.size() == 1 || _body_material[b] == f.material))
      cells.insert(cells.end(), _bodies[b].cells.begin(),
                   _bodies[b].cells.end());
  std::sort(cells.begin(), cells.end());
  return cells;
}

void BodySet::keep_masses(std::span<const char> kept)
{
  // A body that was not kept has an empty matrix (every kept one has
  // entries: its diagonal).
  std::vector<char> missing(_bodies.size(), 0);
  bool any = false;
  for (std::size_t b = 0; b < _bodies.size(); ++b)
  {
    if (!kept[b])
    {
      // Swapped out, not assigned: Eigen 3.4's sparse assignment keeps
      // the old storage allocated.
      BodyMatrix empty(_bodies[b].num_dofs(), _bodies[b].num_dofs());
      _mass[b].swap(empty);
    }
    else if (_mass[b].nonZeros() == 0)
    {
      missing[b] = 1;
      any = true;
    }
  }
  if (!any)
    return;
  // Bodies that came to this rank (a rebalanced run): their masses are
  // assembled again, over their cells only.
  std::vector<BodyMatrix> fresh = create_matrices(missing);
  for (const MaterialForms& f : _forms)
    assemble_by_body(*restrict_to_cells(*f.mass, cells_of(missing, f)),
                     _node_body, _node_local, fresh);
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (missing[b])
      _mass[b].swap(fresh[b]); // no copy (Eigen 3.4 has no sparse move)
}

} // namespace softpack::bodies
