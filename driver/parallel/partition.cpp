#include "partition.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace softpack::parallel
{
namespace
{
/// Give bodies[0..n) the parts first, first + 1, ..., first + ranks - 1.
void bisect(std::span<const double> x, int dim, std::span<const double> w,
            std::vector<int>& bodies, std::size_t begin, std::size_t end,
            int first, int ranks, std::vector<int>& part)
{
  if (ranks == 1)
  {
    for (std::size_t k = begin; k < end; ++k)
      part[bodies[k]] = first;
    return;
  }
  // Cut across the longest extent of the bodies' centres (the first of
  // equals).
  double lo[3], hi[3];
  for (int c = 0; c < dim; ++c)
    lo[c] = hi[c] = x[dim * bodies[begin] + c];
  for (std::size_t k = begin; k < end; ++k)
    for (int c = 0; c < dim; ++c)
    {
      lo[c] = std::min(lo[c], x[dim * bodies[k] + c]);
      hi[c] = std::max(hi[c], x[dim * bodies[k] + c]);
    }
  int d = 0;
  for (int c = 1; c < dim; ++c)
    if (hi[c] - lo[c] > hi[d] - lo[d])
      d = c;
  auto first_it = bodies.begin() + static_cast<std::ptrdiff_t>(begin);
  auto end_it = bodies.begin() + static_cast<std::ptrdiff_t>(end);
  std::sort(first_it, end_it,
            [&](int a, int b)
            {
              const double xa = x[dim * a + d], xb = x[dim * b + d];
              return xa < xb || (xa == xb && a < b);
            });
  // The left side gets ranks / 2 parts and that share of the weight, but
  // at least one body per part on either side.
  const int left_ranks = ranks / 2;
  double total = 0;
  for (std::size_t k = begin; k < end; ++k)
    total += w[bodies[k]];
  const double target = total * left_ranks / ranks;
  std::size_t cut = begin;
  double sum = 0;
  while (cut < end && sum + 0.5 * w[bodies[cut]] < target)
    sum += w[bodies[cut++]];
  cut = std::clamp(cut, begin + left_ranks, end - (ranks - left_ranks));
  bisect(x, dim, w, bodies, begin, cut, first, left_ranks, part);
  bisect(x, dim, w, bodies, cut, end, first + left_ranks, ranks - left_ranks,
         part);
}
} // namespace

std::vector<int> partition_bodies(std::span<const double> centres,
                                  std::span<const double> weights, int ranks,
                                  int dim)
{
  const std::size_t n = weights.size();
  if ((dim != 2 && dim != 3) ||
      centres.size() != static_cast<std::size_t>(dim) * n)
    throw std::invalid_argument(
        "partition_bodies: " + std::to_string(centres.size()) +
        " centre coordinates for " + std::to_string(n) + " bodies in " +
        std::to_string(dim) + "D");
  if (ranks < 1 || static_cast<std::size_t>(ranks) > n)
    throw std::invalid_argument("partition_bodies: " + std::to_string(ranks) +
                                " ranks for " + std::to_string(n) +
                                " bodies (allowed: 1 to the number of bodies)");
  std::vector<int> bodies(n), part(n, 0);
  std::iota(bodies.begin(), bodies.end(), 0);
  bisect(centres, dim, weights, bodies, 0, n, 0, ranks, part);
  return part;
}

namespace
{
/// How much the busiest part's weight exceeds the mean part's (0: even)
double imbalance(std::span<const int> part, std::span<const double> weights,
                 int parts)
{
  std::vector<double> load(parts, 0.0);
  double total = 0;
  for (std::size_t b = 0; b < part.size(); ++b)
  {
    load[part[b]] += weights[b];
    total += weights[b];
  }
  return *std::max_element(load.begin(), load.end()) / (total / parts) - 1;
}

/// Links whose two bodies are in different parts
long cut(std::span<const int> part, std::span<const std::array<int, 2>> links)
{
  return std::count_if(links.begin(), links.end(),
                       [&](const auto& l) { return part[l[0]] != part[l[1]]; });
}
} // namespace

bool split_has_drifted(std::span<const int> now, std::span<const int> fresh,
                       int parts, std::span<const double> weights,
                       std::span<const std::array<int, 2>> links,
                       double tolerance)
{
  if (std::equal(now.begin(), now.end(), fresh.begin(), fresh.end()))
    return false;
  // A rank with more work than the others makes them wait at every
  // exchange; a contact cut between ranks costs messages in every sweep.
  // The floor of a few links keeps contacts that open and close at an
  // interface from moving bodies back and forth.
  constexpr long few_links = 8;
  const double before = imbalance(now, weights, parts),
               after = imbalance(fresh, weights, parts);
  const long cut_before = cut(now, links), cut_after = cut(fresh, links);
  const bool uneven = before > tolerance && after < before;
  const bool scattered = cut_before > (1 + tolerance) * cut_after &&
                         cut_before - cut_after >= few_links &&
                         after <= std::max(before, tolerance);
  return uneven || scattered;
}

} // namespace softpack::parallel
