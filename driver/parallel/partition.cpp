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
void bisect(std::span<const double> x, std::span<const double> w,
            std::vector<int>& bodies, std::size_t begin, std::size_t end,
            int first, int ranks, std::vector<int>& part)
{
  if (ranks == 1)
  {
    for (std::size_t k = begin; k < end; ++k)
      part[bodies[k]] = first;
    return;
  }
  // Cut across the longer extent of the bodies' centres.
  double lo[2] = {x[2 * bodies[begin]], x[2 * bodies[begin] + 1]};
  double hi[2] = {lo[0], lo[1]};
  for (std::size_t k = begin; k < end; ++k)
    for (int d = 0; d < 2; ++d)
    {
      lo[d] = std::min(lo[d], x[2 * bodies[k] + d]);
      hi[d] = std::max(hi[d], x[2 * bodies[k] + d]);
    }
  const int d = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1;
  auto first_it = bodies.begin() + static_cast<std::ptrdiff_t>(begin);
  auto end_it = bodies.begin() + static_cast<std::ptrdiff_t>(end);
  std::sort(first_it, end_it,
            [&](int a, int b)
            {
              const double xa = x[2 * a + d], xb = x[2 * b + d];
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
  bisect(x, w, bodies, begin, cut, first, left_ranks, part);
  bisect(x, w, bodies, cut, end, first + left_ranks, ranks - left_ranks, part);
}
} // namespace

std::vector<int> partition_bodies(std::span<const double> centres,
                                  std::span<const double> weights, int ranks)
{
  const std::size_t n = weights.size();
  if (centres.size() != 2 * n)
    throw std::invalid_argument(
        "partition_bodies: " + std::to_string(centres.size()) +
        " centre coordinates for " + std::to_string(n) + " bodies");
  if (ranks < 1 || static_cast<std::size_t>(ranks) > n)
    throw std::invalid_argument("partition_bodies: " + std::to_string(ranks) +
                                " ranks for " + std::to_string(n) +
                                " bodies (allowed: 1 to the number of bodies)");
  std::vector<int> bodies(n), part(n, 0);
  std::iota(bodies.begin(), bodies.end(), 0);
  bisect(centres, weights, bodies, 0, n, 0, ranks, part);
  return part;
}

} // namespace softpack::parallel
