#include "effective_stiffness.h"
#include "damping.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <stdexcept>

namespace softpack::dynamics
{
namespace
{
/// Boundary slots solved together in 3D: 8 slots, 24 right-hand sides (of
/// 8, 16 and 32 the fastest at 2 mm; docs/performance_3d.md, "Compliance
/// columns by groups")
constexpr std::size_t column_group_slots = 8;

/// The Z-order (Morton) key of a point quantized to 10 bits per axis
std::uint32_t morton_key(const std::array<std::uint32_t, 3>& q)
{
  std::uint32_t key = 0;
  for (int bit = 9; bit >= 0; --bit)
    for (int c = 0; c < 3; ++c)
      key = (key << 1) | ((q[c] >> bit) & 1u);
  return key;
}
} // namespace

EffectiveStiffness::EffectiveStiffness(const bodies::BodySet& bodies,
                                       bool lumped_mass)
    : _mass(&bodies.consistent_mass()),
      _factors(bodies, bodies.consistent_mass()), _bodies(&bodies),
      _dim(bodies.dim())
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
  _groups.resize(bodies.num_bodies());
  _group_of.resize(bodies.num_bodies());
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
  _bodies = &bodies;
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

const std::vector<std::vector<std::int32_t>>&
EffectiveStiffness::column_groups(int b) const
{
  std::vector<std::vector<std::int32_t>>& groups = _groups[b];
  if (!groups.empty())
    return groups;
  const bodies::Body& body = _bodies->body(b);
  const std::span<const double> x = _bodies->reference_coordinates();
  const std::vector<std::int32_t>& nodes = _boundary[b];
  const int d = _dim;
  std::array<double, 3> lo{}, hi{};
  lo.fill(1e300);
  hi.fill(-1e300);
  for (const std::int32_t n : nodes)
    for (int c = 0; c < d; ++c)
    {
      lo[c] = std::min(lo[c], x[d * body.nodes[n] + c]);
      hi[c] = std::max(hi[c], x[d * body.nodes[n] + c]);
    }
  std::vector<std::uint32_t> key(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    std::array<std::uint32_t, 3> q{};
    for (int c = 0; c < d; ++c)
    {
      const double span = hi[c] - lo[c];
      const double t =
          span > 0 ? (x[d * body.nodes[nodes[i]] + c] - lo[c]) / span : 0;
      q[c] = static_cast<std::uint32_t>(std::min(t * 1024, 1023.0));
    }
    key[i] = morton_key(q);
  }
  std::vector<std::int32_t> order(nodes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::int32_t i, std::int32_t j)
                   { return key[i] < key[j]; });
  _group_of[b].assign(nodes.size(), -1);
  for (std::size_t i = 0; i < order.size(); i += column_group_slots)
  {
    const std::size_t end = std::min(order.size(), i + column_group_slots);
    for (std::size_t k = i; k < end; ++k)
      _group_of[b][order[k]] = static_cast<std::int32_t>(groups.size());
    groups.emplace_back(order.begin() + i, order.begin() + end);
  }
  return groups;
}

void EffectiveStiffness::prepare_column_blocks(int b,
                                               std::span<const int> slots) const
{
  const std::vector<std::int32_t>& nodes = _boundary[b];
  std::vector<Column>& C = _columns[b];
  std::vector<char>& ready = _column_ready[b];
  const std::vector<std::vector<std::int32_t>>& groups = column_groups(b);
  const int d = _dim;
  for (int slot : slots)
  {
    if (ready[slot])
      continue;
    const std::vector<std::int32_t>& group = groups[_group_of[b][slot]];
    const int m = d * static_cast<int>(group.size());
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(_factors.rows(b), m);
    for (std::size_t s = 0; s < group.size(); ++s)
      for (int c = 0; c < d; ++c)
        E(d * nodes[group[s]] + c, d * s + c) = 1;
    const Eigen::MatrixXd X = _factors.solve(b, E);
    for (std::size_t s = 0; s < group.size(); ++s)
    {
      for (int c = 0; c < d; ++c)
      {
        Column& rows = C[d * group[s] + c];
        rows.resize(d * nodes.size());
        for (std::size_t i = 0; i < nodes.size(); ++i)
          for (int r = 0; r < d; ++r)
            rows[d * i + r] = X(d * nodes[i] + r, d * s + c);
      }
      ready[group[s]] = 1;
    }
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
