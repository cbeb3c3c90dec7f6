#include "effective_stiffness.h"
#include "damping.h"

#include <stdexcept>

namespace softpack::dynamics
{

EffectiveStiffness::EffectiveStiffness(const bodies::BodySet& bodies,
                                       bool lumped_mass)
    : _mass(&bodies.consistent_mass()),
      _factors(bodies, bodies.consistent_mass()), _dim(bodies.dim())
{
  if (lumped_mass)
  {
    build_lumped(bodies);
    _mass = &_lumped;
  }
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    _boundary.push_back(body.boundary_nodes);
    _slot.emplace_back(body.nodes.size(), -1);
    for (std::size_t i = 0; i < body.boundary_nodes.size(); ++i)
      _slot[b][body.boundary_nodes[i]] = static_cast<std::int32_t>(i);
  }
  _columns.resize(bodies.num_bodies());
  _column_ready.resize(bodies.num_bodies());
}

void EffectiveStiffness::build_lumped(const bodies::BodySet& bodies)
{
  // On the stiffness pattern, for the bodies whose consistent masses the
  // body set keeps (BodySet::kept_masses): the others' stay empty.
  _lumped = bodies.create_mass_matrices();
  for (int b = 0; b < bodies.num_bodies(); ++b)
    for (int col = 0; col < _lumped[b].outerSize(); ++col)
      for (bodies::BodyMatrix::InnerIterator it(_lumped[b], col); it; ++it)
        it.valueRef() =
            it.row() == it.col() ? bodies.lumped_mass()[b][it.row()] : 0.0;
}

void EffectiveStiffness::set_local(const bodies::BodySet& bodies)
{
  if (_mass == &_lumped)
    build_lumped(bodies);
  _factors = BodyFactors(bodies, bodies.consistent_mass());
  for (std::vector<Column>& C : _columns)
    C.clear();
  for (std::vector<char>& ready : _column_ready)
    ready.clear();
}

void EffectiveStiffness::prepare_columns(int b,
                                         std::span<const int> slots) const
{
  const std::vector<std::int32_t>& nodes = _boundary[b];
  std::vector<Column>& C = _columns[b];
  std::vector<char>& ready = _column_ready[b];
  const int d = _dim;
  if (ready.empty())
  {
    C.assign(d * nodes.size(), Column());
    ready.assign(nodes.size(), 0);
  }
  if (_factors.solves_blocks())
  {
    prepare_column_blocks(b, slots);
    return;
  }
  Eigen::VectorXd e = Eigen::VectorXd::Zero(_factors.rows(b));
  for (int slot : slots)
  {
    if (ready[slot])
      continue;
    for (int c = 0; c < d; ++c)
    {
      const int dof = d * nodes[slot] + c;
      e[dof] = 1;
      const Eigen::VectorXd x = _factors.solve(b, e);
      e[dof] = 0;
      Column& rows = C[d * slot + c];
      rows.resize(d * nodes.size());
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int k = 0; k < d; ++k)
          rows[d * i + k] = x[d * nodes[i] + k];
    }
    ready[slot] = 1;
  }
}

void EffectiveStiffness::prepare_column_blocks(int b,
                                               std::span<const int> slots) const
{
  const std::vector<std::int32_t>& nodes = _boundary[b];
  std::vector<Column>& C = _columns[b];
  std::vector<char>& ready = _column_ready[b];
  const int d = _dim;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(_factors.rows(b), d);
  for (int slot : slots)
  {
    if (ready[slot])
      continue;
    for (int c = 0; c < d; ++c)
      E(d * nodes[slot] + c, c) = 1;
    const Eigen::MatrixXd X = _factors.solve(b, E);
    for (int c = 0; c < d; ++c)
    {
      E(d * nodes[slot] + c, c) = 0;
      Column& rows = C[d * slot + c];
      rows.resize(d * nodes.size());
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (int r = 0; r < d; ++r)
          rows[d * i + r] = X(d * nodes[i] + r, c);
    }
    ready[slot] = 1;
  }
}

void EffectiveStiffness::factorize(const std::vector<bodies::BodyMatrix>& K,
                                   double mass_coefficient,
                                   double stiffness_coefficient)
{
  const RayleighDamping::Combination kbar{mass_coefficient,
                                          stiffness_coefficient};
  const bool ok = _factors.factorize([&](int b, bodies::BodyMatrix& A)
                                     { combine(kbar, mass(b), K[b], A); });
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
