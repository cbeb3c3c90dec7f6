// The bodies' matrices: one sparse pattern per body, the tangent assembled
// into it, and the masses a rank keeps (its own bodies and every rigid one).
#include "BodySet.h"

#include "body_assembly.h"
#include <stdexcept>

namespace softpack::bodies
{

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
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(36 * body.cells.size());
    for (const std::array<std::int32_t, 3>& cell : body.cell_nodes)
      for (std::int32_t ni : cell)
        for (std::int32_t nj : cell)
          for (int ci = 0; ci < 2; ++ci)
            for (int cj = 0; cj < 2; ++cj)
            {
              const int row = 2 * ni + ci, col = 2 * nj + cj;
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

void BodySet::tangent(std::vector<BodyMatrix>& K) const
{
  _assembly->tangent(K, _bodies, _reference_x, _u, _owned);
}

void BodySet::build_mass()
{
  _mass = create_matrices();
  _assembly->mass(_mass, _bodies, _reference_x);
  _lumped_mass = _assembly->lumped_mass(_bodies, _reference_x);
}

void BodySet::set_owned(std::vector<char> owned)
{
  if (owned.size() != _bodies.size())
    throw std::invalid_argument(
        "BodySet::set_owned: " + std::to_string(owned.size()) + " flags for " +
        std::to_string(_bodies.size()) + " bodies");
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
      Eigen::VectorXd().swap(_lumped_mass[b]);
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
  // assembled again.
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

} // namespace softpack::bodies
