#include "effective_stiffness.h"
#include "damping.h"

#include <stdexcept>

namespace softpack::dynamics
{

EffectiveStiffness::EffectiveStiffness(const bodies::BodySet& bodies,
                                       bool lumped_mass,
                                       std::span<const char> owned)
    : _mass(&bodies.consistent_mass()), _factors(bodies.num_bodies()),
      _owned(owned.begin(), owned.end())
{
  if (lumped_mass) // the lumped masses on the stiffness pattern
  {
    _lumped = bodies.create_matrices();
    for (int b = 0; b < bodies.num_bodies(); ++b)
      for (int col = 0; col < _lumped[b].outerSize(); ++col)
        for (bodies::BodyMatrix::InnerIterator it(_lumped[b], col); it; ++it)
          it.valueRef() =
              it.row() == it.col() ? bodies.lumped_mass()[b][it.row()] : 0.0;
    _mass = &_lumped;
  }
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    if (_owned.empty() || _owned[b])
      _factors[b].analyzePattern(mass(b));
    const bodies::Body& body = bodies.body(b);
    _boundary.push_back(body.boundary_nodes);
    _slot.emplace_back(body.nodes.size(), -1);
    for (std::size_t i = 0; i < body.boundary_nodes.size(); ++i)
      _slot[b][body.boundary_nodes[i]] = static_cast<std::int32_t>(i);
  }
  _columns.resize(bodies.num_bodies());
  _column_ready.resize(bodies.num_bodies());
}

void EffectiveStiffness::prepare_columns(int b,
                                         std::span<const int> slots) const
{
  const std::vector<std::int32_t>& nodes = _boundary[b];
  std::vector<Column>& C = _columns[b];
  std::vector<char>& ready = _column_ready[b];
  if (ready.empty())
  {
    C.assign(2 * nodes.size(), Column());
    ready.assign(nodes.size(), 0);
  }
  Eigen::VectorXd e = Eigen::VectorXd::Zero(_factors[b].rows());
  for (int slot : slots)
  {
    if (ready[slot])
      continue;
    for (int c = 0; c < 2; ++c)
    {
      const int dof = 2 * nodes[slot] + c;
      e[dof] = 1;
      C[2 * slot + c] = _factors[b].solve(e).cast<float>();
      e[dof] = 0;
    }
    ready[slot] = 1;
  }
}

void EffectiveStiffness::factorize(const std::vector<bodies::BodyMatrix>& K,
                                   double mass_coefficient,
                                   double stiffness_coefficient)
{
  bool ok = true;
  const int nb = static_cast<int>(_factors.size());
  const RayleighDamping::Combination kbar{mass_coefficient,
                                          stiffness_coefficient};
#pragma omp parallel for schedule(dynamic) reduction(&& : ok) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
  {
    if (!_owned.empty() && !_owned[b])
      continue;
    bodies::BodyMatrix scratch = mass(b); // the pattern; values replaced
    combine(kbar, mass(b), K[b], scratch);
    _factors[b].factorize(scratch);
    ok = ok && _factors[b].info() == Eigen::Success &&
         (_factors[b].vectorD().array() > 0).all();
  }
  // No throwing inside the parallel loop.
  if (!ok)
    throw std::runtime_error("the iteration matrix of a body is not positive "
                             "definite (element inverted or time step too "
                             "large)");
  // The old columns are stale: free them (memory follows the contacts).
  for (std::size_t b = 0; b < _columns.size(); ++b)
  {
    _column_ready[b].clear();
    _columns[b].clear();
    _columns[b].shrink_to_fit();
  }
  ++_count;
}

} // namespace softpack::dynamics
