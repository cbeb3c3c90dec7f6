// The level-set separator behind the two-thread NLGS sweep.
#include "sweep_split.h"

#include "coupling_graph.h"

#include <algorithm>
#include <limits>
#include <span>

namespace softpack::contact
{
namespace
{
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
  // sum): a spread term's are held for the separator, the others split.
  std::vector<char> held(n, 0);
  for (const auto& term : W.rank_one_terms())
    if (!term.local)
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
  // 0, 1: the parts; 2: the separator
  std::vector<char> side(n, 2);
  for (std::size_t a = 0; a < n; ++a)
    if (!held[a])
      side[a] = global[a] < cut ? 0 : global[a] > cut ? 1 : 2;
  // A local term with contacts in both parts would have both threads
  // update its sum: its part 1 contacts are swept with the separator
  for (const auto& term : W.rank_one_terms())
    if (term.local and
        std::any_of(term.contacts.begin(), term.contacts.end(),
                    [&side](std::int32_t c) { return side[c] == 0; }))
      for (const std::int32_t c : term.contacts)
        side[c] = side[c] == 1 ? 2 : side[c];
  for (std::size_t a = 0; a < n; ++a)
  {
    const auto c = static_cast<std::int32_t>(a);
    (side[a] == 2 ? split.separator : split.part[side[a]]).push_back(c);
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
