#include "rebalance.h"

#include "partition.h"
#include <stdexcept>
#include <string>

namespace softpack::parallel
{

std::vector<double> body_centres(const bodies::BodySet& bodies,
                                 std::span<const double> x,
                                 std::span<const int> which)
{
  const int d = bodies.dim();
  std::vector<double> centres(d * bodies.num_bodies(), 0.0);
  for (const int b : which)
  {
    const bodies::Body& body = bodies.body(b);
    for (std::int32_t node : body.nodes)
      for (int c = 0; c < d; ++c)
        centres[d * b + c] += x[d * node + c] / body.nodes.size();
  }
  return centres;
}

std::vector<int>
drifted_split(const Distribution& distribution, const bodies::BodySet& bodies,
              std::span<const double> x, std::span<const double> weights,
              std::span<const std::array<int, 2>> links, double tolerance)
{
  const Communicator& comm = distribution.comm();
  if (!comm.distributed())
    return {};
  // One owner computes each centre: the sum is its value, bit for bit.
  std::vector<double> centres = body_centres(bodies, x, bodies.local_bodies());
  comm.sum(centres);
  std::vector<int> fresh =
      partition_bodies(centres, weights, comm.size(), bodies.dim());
  if (!split_has_drifted(distribution.index_map().body_rank(), fresh,
                         comm.size(), weights, links, tolerance))
    return {};
  return fresh;
}

namespace
{
/// Visit body b's entries that travel with it: displacement, reference
/// coordinates, then the given (nonempty) vectors
template <typename Visit>
void body_entries(bodies::BodySet& bodies, int b,
                  std::span<std::vector<double>* const> vectors, Visit&& visit)
{
  std::vector<std::span<double>> all = {bodies.displacement(),
                                        bodies.stored_reference_coordinates()};
  for (std::vector<double>* v : vectors)
    if (!v->empty())
      all.emplace_back(*v);
  const int d = bodies.dim();
  for (const std::span<double> v : all)
    for (const std::int32_t node : bodies.body(b).nodes)
      for (int c = 0; c < d; ++c)
        visit(v[d * node + c]);
}

/// The internal variables of the bodies that leave this rank sent to
/// their new owners, cell by cell (a third all-to-all, when a law has
/// them); what arrives from each sender, in the senders' rank order
std::vector<double> move_internal(const Communicator& comm,
                                  std::span<const int> before,
                                  std::span<const int> split,
                                  const bodies::BodySet& bodies)
{
  const int stride = bodies.internal_stride();
  if (stride == 0)
    return {};
  const int rank = comm.rank();
  std::vector<std::vector<double>> to_rank(comm.size());
  for (int r = 0; r < comm.size(); ++r)
  {
    if (r == rank)
      continue;
    std::vector<char> leaving(before.size());
    for (std::size_t b = 0; b < before.size(); ++b)
      leaving[b] = before[b] == rank && split[b] == r;
    to_rank[r] = bodies::pick_cells(bodies.internal_variables(), stride,
                                    bodies.cell_body(), leaving);
  }
  return comm.exchange_items(to_rank);
}

/// Put the arriving bodies' internal variables (move_internal) in place
void take_internal(const Communicator& comm, std::span<const int> before,
                   std::span<const int> after, bodies::BodySet& bodies,
                   std::span<const double> in)
{
  const int stride = bodies.internal_stride(), rank = comm.rank();
  std::size_t k = 0;
  for (int r = 0; r < comm.size() && stride > 0; ++r)
  {
    if (r == rank)
      continue;
    std::vector<char> arriving(before.size());
    for (std::size_t b = 0; b < before.size(); ++b)
      arriving[b] = before[b] == r && after[b] == rank;
    k += bodies::place_cells(bodies.internal_variables(), stride,
                             bodies.cell_body(), arriving, in.subspan(k));
  }
  if (k != in.size())
    throw std::logic_error("move_bodies: " + std::to_string(in.size()) +
                           " internal variables received, " +
                           std::to_string(k) + " expected");
}
} // namespace

void move_bodies(Distribution& distribution, std::vector<int> split,
                 bodies::BodySet& bodies,
                 std::span<std::vector<double>* const> vectors)
{
  const Communicator& comm = distribution.comm();
  const int rank = comm.rank(), nb = bodies.num_bodies();
  const std::vector<int> before = distribution.index_map().body_rank();
  if (split.size() != before.size())
    throw std::invalid_argument("move_bodies: a rank for each body");
  // The moving bodies' entries and cell lists (a rigid body's are on
  // every rank)
  std::vector<std::vector<double>> to_rank(comm.size());
  std::vector<std::vector<std::int32_t>> lists_to_rank(comm.size());
  for (int b = 0; b < nb; ++b)
    if (before[b] == rank && split[b] != rank)
    {
      body_entries(bodies, b, vectors,
                   [&](double x) { to_rank[split[b]].push_back(x); });
      if (!bodies.rigid(b))
      {
        const std::vector<std::int32_t> lists = bodies.cell_lists(b);
        std::vector<std::int32_t>& out = lists_to_rank[split[b]];
        out.insert(out.end(), lists.begin(), lists.end());
      }
    }
  // Received in the senders' rank order, each sender's bodies in order
  const std::vector<double> in = comm.exchange_items(to_rank);
  const std::vector<std::int32_t> lists_in = comm.exchange_items(lists_to_rank);
  const std::vector<double> internal_in =
      move_internal(comm, before, split, bodies);
  long moved = 0;
  for (int b = 0; b < nb; ++b)
    moved += split[b] != before[b];
  distribution.count_rebalance(moved);
  distribution.assign(std::move(split), bodies);
  for (std::vector<double>* v : vectors)
    if (!v->empty())
      bodies.remap(*v);
  const std::vector<int>& after = distribution.index_map().body_rank();
  std::size_t k = 0, l = 0;
  for (int r = 0; r < comm.size(); ++r)
    for (int b = 0; b < nb; ++b)
      if (before[b] == r && r != rank && after[b] == rank)
      {
        body_entries(bodies, b, vectors, [&](double& x) { x = in[k++]; });
        if (!bodies.rigid(b))
          l += bodies.take_cell_lists(b, std::span(lists_in).subspan(l));
      }
  if (k != in.size() || l != lists_in.size())
    throw std::logic_error("move_bodies: " + std::to_string(in.size()) +
                           " entries and " + std::to_string(lists_in.size()) +
                           " list entries received, " + std::to_string(k) +
                           " and " + std::to_string(l) + " expected");
  take_internal(comm, before, after, bodies, internal_in);
  // The arriving bodies' masses from their reference coordinates and
  // cells, now here
  bodies.set_local(distribution.index_map().local_bodies());
}

} // namespace softpack::parallel
