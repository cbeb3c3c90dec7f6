// The level-set separator behind the two-thread NLGS sweep.
#include "sweep_split.h"

#include <algorithm>
#include <limits>
#include <span>

namespace softpack::contact
{
namespace
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
Graph coupling_graph(const DelassusMatrixD<D>& W, const std::vector<char>& held)
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
std::vector<std::int32_t> levels_from(const Graph& g, std::int32_t start,
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

/// Each contact's level in the sequence of all components' levels laid end
/// to end (a component starts at a pseudo-peripheral contact, so that its
/// levels are many and thin); the held contacts have none (-1).
std::vector<std::int32_t> global_levels(const Graph& g, std::size_t n,
                                        const std::vector<char>& held,
                                        std::int32_t& num_levels)
{
  std::vector<std::int32_t> probe(n, -1), level(n, -1), global(n, -1);
  num_levels = 0;
  for (std::size_t s = 0; s < n; ++s)
  {
    if (level[s] >= 0 or held[s])
      continue;
    const std::int32_t far =
        levels_from(g, static_cast<std::int32_t>(s), probe).back();
    std::int32_t deepest = 0;
    for (const std::int32_t c : levels_from(g, far, level))
    {
      global[c] = num_levels + level[c];
      deepest = std::max(deepest, level[c]);
    }
    num_levels += deepest + 1;
  }
  return global;
}
template <int D> SweepSplit split_contacts(const DelassusMatrixD<D>& W)
{
  const std::size_t n = W.num_contacts();
  SweepSplit split;
  if (n < 3)
  {
    for (std::size_t a = 0; a < n; ++a)
      split.part[0].push_back(static_cast<std::int32_t>(a));
    return split;
  }
  // The contacts of a rank-one term all read one another (through its
  // sum): they are held for the separator, the others split.
  std::vector<char> held(n, 0);
  for (const auto& term : W.rank_one_terms())
    for (const std::int32_t c : term.contacts)
      held[c] = 1;
  const Graph g = coupling_graph(W, held);
  std::int32_t num_levels = 0;
  const std::vector<std::int32_t> global =
      global_levels(g, n, held, num_levels);
  // A contact's work in a sweep: its local solve and its row's blocks.
  std::vector<double> work(num_levels, 0.0);
  for (std::size_t a = 0; a < n; ++a)
    if (!held[a])
      work[global[a]] += 1.0 + static_cast<double>(W.row_columns(a).size());
  double total = 0;
  for (const double w : work)
    total += w;
  std::int32_t cut = 0;
  double best = std::numeric_limits<double>::infinity(), before = 0;
  for (std::int32_t k = 0; k < num_levels; ++k)
  {
    const double after = total - before - work[k];
    const double cost = std::max(before, after) + work[k];
    if (cost < best)
    {
      best = cost;
      cut = k;
    }
    before += work[k];
  }
  for (std::size_t a = 0; a < n; ++a)
  {
    const auto c = static_cast<std::int32_t>(a);
    if (held[a])
      split.separator.push_back(c);
    else if (global[a] < cut)
      split.part[0].push_back(c);
    else if (global[a] > cut)
      split.part[1].push_back(c);
    else
      split.separator.push_back(c);
  }
  return split;
}
} // namespace

SweepSplit split_for_two_threads(const DelassusMatrix& W)
{
  return split_contacts(W);
}

SweepSplit split_for_two_threads(const DelassusMatrix3D& W)
{
  return split_contacts(W);
}

} // namespace softpack::contact
