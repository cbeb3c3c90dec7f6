#include "effective_stiffness.h"

#include <stdexcept>

namespace softpack::dynamics
{

EffectiveStiffness::EffectiveStiffness(const bodies::BodySet& bodies,
                                       bool lumped_mass,
                                       std::span<const char> owned)
    : _mass(bodies.create_matrices()), _kbar(bodies.create_matrices()),
      _factors(bodies.num_bodies()), _owned(owned.begin(), owned.end())
{
  // Copy each mass onto the stiffness pattern (a superset of both mass
  // patterns), so that a M + c K is a plain combination of value arrays.
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    bodies::BodyMatrix& M = _mass[b];
    for (int col = 0; col < M.outerSize(); ++col)
      for (bodies::BodyMatrix::InnerIterator it(M, col); it; ++it)
        it.valueRef() =
            lumped_mass
                ? (it.row() == it.col() ? bodies.lumped_mass()[b][it.row()]
                                        : 0.0)
                : bodies.consistent_mass()[b].coeff(it.row(), it.col());
    if (_owned.empty() || _owned[b])
      _factors[b].analyzePattern(_kbar[b]);
    const bodies::Body& body = bodies.body(b);
    _boundary.push_back(body.boundary_nodes);
    _slot.emplace_back(body.nodes.size(), -1);
    for (std::size_t i = 0; i < body.boundary_nodes.size(); ++i)
      _slot[b][body.boundary_nodes[i]] = static_cast<std::int32_t>(i);
  }
  _compliance.resize(bodies.num_bodies());
  _columns.resize(bodies.num_bodies());
  _column_ready.resize(bodies.num_bodies());
}

const Eigen::MatrixXd&
EffectiveStiffness::boundary_compliance(int b, std::span<const int> slots) const
{
  const std::vector<std::int32_t>& nodes = _boundary[b];
  const int m = 2 * static_cast<int>(nodes.size());
  Eigen::MatrixXd& G = _compliance[b];
  std::vector<Eigen::VectorXd>& C = _columns[b];
  std::vector<char>& ready = _column_ready[b];
  if (ready.empty())
  {
    G.resize(m, m);
    C.assign(m, Eigen::VectorXd());
    ready.assign(nodes.size(), 0);
  }
  Eigen::VectorXd e = Eigen::VectorXd::Zero(_kbar[b].rows());
  for (int slot : slots)
  {
    if (ready[slot])
      continue;
    for (int c = 0; c < 2; ++c)
    {
      const int j = 2 * slot + c, dof = 2 * nodes[slot] + c;
      e[dof] = 1;
      C[j] = _factors[b].solve(e);
      const Eigen::VectorXd& x = C[j];
      e[dof] = 0;
      for (int i = 0; i < m; ++i)
        G(i, j) = x[2 * nodes[i / 2] + i % 2];
    }
    ready[slot] = 1;
  }
  return G;
}

void EffectiveStiffness::factorize(const std::vector<bodies::BodyMatrix>& K,
                                   double mass_coefficient,
                                   double stiffness_coefficient)
{
  bool ok = true;
#pragma omp parallel for schedule(dynamic) reduction(&& : ok) if (_kbar.size() >= 16)
  for (std::size_t b = 0; b < _kbar.size(); ++b)
  {
    if (!_owned.empty() && !_owned[b])
      continue;
    const double* m = _mass[b].valuePtr();
    const double* k = K[b].valuePtr();
    double* a = _kbar[b].valuePtr();
    for (Eigen::Index i = 0; i < _kbar[b].nonZeros(); ++i)
      a[i] = mass_coefficient * m[i] + stiffness_coefficient * k[i];
    _factors[b].factorize(_kbar[b]);
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
