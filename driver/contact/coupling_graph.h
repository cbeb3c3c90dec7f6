#pragma once
// The contacts' coupling graph (W's stored blocks) and its breadth-first
// levels: the sweep split's level sets (sweep_split.cpp) and a problem's
// frictionless sets (problem_structure.cpp, frictionless_condensation.cpp)
// walk the same graph.
#include "DelassusMatrix.h"
#include "problem.h"

#include <cstdint>
#include <span>
#include <vector>

namespace softpack::contact
{
/// Adjacency of the contacts (compressed rows), symmetric: a block W_ab or
/// W_ba couples a and b (a dropped small block may leave only one of them).
struct Graph
{
  std::vector<std::int32_t> offsets, neighbours;
  std::span<const std::int32_t> of(std::int32_t a) const
  {
    return {neighbours.data() + offsets[a],
            static_cast<std::size_t>(offsets[a + 1] - offsets[a])};
  }
};

/// The graph of the stored blocks between contacts not `held` (the
/// held ones left without edges)
template <int D>
inline Graph coupling_graph(const DelassusMatrixD<D>& W,
                            const std::vector<char>& held)
{
  const std::size_t n = W.num_contacts();
  Graph g;
  g.offsets.assign(n + 1, 0);
  for (std::size_t a = 0; a < n; ++a)
    for (const std::int32_t b : W.row_columns(a))
      if (!held[a] and !held[b])
      {
        ++g.offsets[a + 1];
        ++g.offsets[b + 1];
      }
  for (std::size_t a = 0; a < n; ++a)
    g.offsets[a + 1] += g.offsets[a];
  g.neighbours.resize(g.offsets[n]);
  std::vector<std::int32_t> next(g.offsets.begin(), g.offsets.end() - 1);
  for (std::size_t a = 0; a < n; ++a)
    for (const std::int32_t b : W.row_columns(a))
      if (!held[a] and !held[b])
      {
        g.neighbours[next[a]++] = b;
        g.neighbours[next[b]++] = static_cast<std::int32_t>(a);
      }
  return g;
}

/// Breadth-first levels from `start` over the contacts not yet levelled
/// (level -1); returns the visiting order (the farthest contact last).
inline std::vector<std::int32_t> levels_from(const Graph& g, std::int32_t start,
                                             std::vector<std::int32_t>& level)
{
  std::vector<std::int32_t> order{start};
  level[start] = 0;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (const std::int32_t b : g.of(order[i]))
      if (level[b] < 0)
      {
        level[b] = level[order[i]] + 1;
        order.push_back(b);
      }
  return order;
}

/// The frictionless contacts (friction 0, no cohesion) not `excluded`, in
/// the sets W's stored blocks connect (either way), each in the order a
/// breadth-first walk from its first contact reached it
template <int D>
std::vector<std::vector<std::int32_t>>
frictionless_sets(const FrictionContactProblem<D>& problem,
                  std::vector<char> excluded)
{
  const std::size_t n = problem.num_contacts();
  for (std::size_t a = 0; a < n; ++a)
    excluded[a] =
        excluded[a] or problem.friction[a] != 0 or problem.cohesion_of(a) != 0;
  const Graph g = coupling_graph(problem.W, excluded);
  std::vector<std::int32_t> level(n, -1);
  std::vector<std::vector<std::int32_t>> sets;
  for (std::size_t a = 0; a < n; ++a)
    if (!excluded[a] and level[a] < 0)
      sets.push_back(levels_from(g, static_cast<std::int32_t>(a), level));
  return sets;
}

} // namespace softpack::contact
