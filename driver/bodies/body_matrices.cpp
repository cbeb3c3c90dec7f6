// The bodies' matrices: one sparse pattern per body, the tangent assembled
// into it, and the masses kept (the local bodies' and every rigid one's).
#include "BodySet.h"
#include "nodal_volumetric.h"

#include "body_assembly.h"
#include <limits>
#include <stdexcept>

namespace softpack::bodies
{

std::vector<BodyMatrix> BodySet::create_matrices() const
{
  return create_matrices(_local_flag);
}

std::vector<BodyMatrix> BodySet::create_mass_matrices() const
{
  return create_matrices(kept_masses());
}

std::vector<BodyMatrix>
BodySet::create_matrices(std::span<const char> only) const
{
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
    const int d = body.dim, n = d * (d + 1);
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(n * n * body.cells.size());
    for (const CellNodes& cell : body.cell_nodes)
      for (std::int32_t ni : cell)
        for (std::int32_t nj : cell)
          for (int ci = 0; ci < d; ++ci)
            for (int cj = 0; cj < d; ++cj)
            {
              const int row = d * ni + ci, col = d * nj + cj;
              if (stored_entry(row, col))
                pattern.emplace_back(row, col, 0.0);
            }
    if (const forms::MaterialForms* law = _materials[_body_material[b]].law;
        law && law->nodal_volumetric)
      add_nodal_pattern(body, pattern);
    // Built in place: Eigen 3.4's sparse matrix has no move constructor,
    // so a push_back would copy it.
    BodyMatrix& A = matrices.emplace_back(body.num_dofs(), body.num_dofs());
    A.setFromTriplets(pattern.begin(), pattern.end());
    A.makeCompressed();
  }
  return matrices;
}

void BodySet::tangent(std::vector<BodyMatrix>& K) const
{
  _assembly->tangent(K, _bodies, _reference_x, _u, _local_flag);
}

void BodySet::build_mass(bool all)
{
  if (!all)
  {
    _mass = create_matrices(std::vector<char>(_bodies.size(), 0));
    _lumped_mass.assign(_bodies.size(), Eigen::VectorXd());
    return;
  }
  _mass = create_matrices(std::vector<char>(_bodies.size(), 1));
  _assembly->mass(_mass, _bodies, _reference_x);
  _lumped_mass = _assembly->lumped_mass(_bodies, _reference_x);
}

void BodySet::set_local(std::vector<int> local)
{
  std::vector<char> flag(_bodies.size(), 0);
  for (std::size_t k = 0; k < local.size(); ++k)
  {
    const int b = local[k];
    if (b < 0 || b >= num_bodies() || (k > 0 && b <= local[k - 1]))
      throw std::invalid_argument(
          "BodySet::set_local: body " + std::to_string(b) + " of " +
          std::to_string(_bodies.size()) +
          " bodies out of range or out of increasing order");
    flag[b] = 1;
  }
  const std::vector<char> kept = kept_masses(flag);
  keep_masses(kept);
  keep_cell_lists(kept);
  _local = std::move(local);
  _local_flag = std::move(flag);
  mark_local_nodes();
  // The other ranks' bodies' internal variables are theirs to relax: a
  // read of one here shows as NaN instead of passing for a value
  for (std::size_t c = 0; c < _cell_body.size(); ++c)
    if (!_local_flag[_cell_body[c]] && _assembly->has_internal(_cell_body[c]))
      std::fill_n(_internal.begin() + c * _internal_stride, _internal_stride,
                  std::numeric_limits<double>::quiet_NaN());
}

std::vector<char> BodySet::kept_masses(std::span<const char> local) const
{
  std::vector<char> kept(_bodies.size());
  for (std::size_t b = 0; b < kept.size(); ++b)
    kept[b] = local[b] || rigid(static_cast<int>(b));
  return kept;
}

void BodySet::mark_local_nodes()
{
  _local_node.assign(num_dofs() / _dim, 0);
  for (const int b : _local)
    for (const std::int32_t node : _bodies[b].nodes)
      _local_node[node] = 1;
}

void BodySet::keep_masses(std::span<const char> kept)
{
  // A body that was not kept has an empty matrix (every kept one has
  // entries: its diagonal). Those that became local (a rebalanced run)
  // are assembled again, over the cells they brought: checked before
  // anything is freed.
  std::vector<char> missing(_bodies.size(), 0);
  bool any = false;
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (kept[b] && _mass[b].nonZeros() == 0)
    {
      if (_bodies[b].cells.empty())
        throw std::logic_error("BodySet::set_local: body " + std::to_string(b) +
                               " became local without its cells "
                               "(take_cell_lists)");
      missing[b] = 1;
      any = true;
    }
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (!kept[b])
    {
      // Swapped out, not assigned: Eigen 3.4's sparse assignment keeps
      // the old storage allocated.
      BodyMatrix empty(_bodies[b].num_dofs(), _bodies[b].num_dofs());
      _mass[b].swap(empty);
      Eigen::VectorXd().swap(_lumped_mass[b]);
    }
  if (!any)
    return;
  std::vector<BodyMatrix> fresh = create_matrices(missing);
  _assembly->mass(fresh, _bodies, _reference_x, missing);
  std::vector<Eigen::VectorXd> lumped =
      _assembly->lumped_mass(_bodies, _reference_x, missing);
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (missing[b])
    {
      _mass[b].swap(fresh[b]); // no copy (Eigen 3.4 has no sparse move)
      _lumped_mass[b].swap(lumped[b]);
    }
}

void BodySet::keep_cell_lists(std::span<const char> kept)
{
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (!kept[b])
    {
      Body& body = _bodies[b];
      std::vector<std::int32_t>().swap(body.cells);
      std::vector<CellNodes>().swap(body.cell_nodes);
      std::vector<std::int32_t>().swap(body.input_position);
    }
}

std::vector<std::int32_t> BodySet::cell_lists(int b) const
{
  const Body& body = _bodies[b];
  std::vector<std::int32_t> out;
  out.reserve(1 + (body.dim + 2) * body.cells.size() +
              body.input_position.size());
  out.push_back(static_cast<std::int32_t>(body.cells.size()));
  out.insert(out.end(), body.cells.begin(), body.cells.end());
  for (const CellNodes& cell : body.cell_nodes)
    out.insert(out.end(), cell.begin(), cell.end());
  out.insert(out.end(), body.input_position.begin(), body.input_position.end());
  return out;
}

std::size_t BodySet::take_cell_lists(int b, std::span<const std::int32_t> in)
{
  Body& body = _bodies[b];
  const std::size_t nc = in.empty() ? 0 : in[0];
  const std::size_t n = 1 + (body.dim + 2) * nc + body.nodes.size();
  if (in.size() < n)
    throw std::invalid_argument("BodySet::take_cell_lists: body " +
                                std::to_string(b) + " needs " +
                                std::to_string(n) + " entries, " +
                                std::to_string(in.size()) + " given");
  auto at = in.begin() + 1;
  body.cells.assign(at, at + nc);
  at += nc;
  body.cell_nodes.assign(nc, CellNodes());
  for (CellNodes& cell : body.cell_nodes)
    for (int i = 0; i <= body.dim; ++i)
      cell[i] = *at++;
  body.input_position.assign(at, at + body.nodes.size());
  return n;
}

void BodySet::require_every_cell(const char* what) const
{
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (_bodies[b].cells.empty())
      throw std::logic_error(std::string("BodySet::") + what + ": body " +
                             std::to_string(b) +
                             "'s cells are not kept here (set_local)");
}

} // namespace softpack::bodies
