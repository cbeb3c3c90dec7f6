#include "ownership.h"

#include "partition.h"
#include <limits>
#include <stdexcept>
#include <string>

namespace softpack::parallel
{

namespace
{
/// Centre of each body at the node coordinates x (interleaved); of the
/// flagged bodies only when `only` is given (the others' stay zero)
std::vector<double> body_centres(const bodies::BodySet& bodies,
                                 std::span<const double> x,
                                 std::span<const char> only = {})
{
  std::vector<double> centres(2 * bodies.num_bodies(), 0.0);
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    if (!only.empty() && !only[b])
      continue;
    const bodies::Body& body = bodies.body(b);
    for (std::int32_t node : body.nodes)
      for (int c = 0; c < 2; ++c)
        centres[2 * b + c] += x[2 * node + c] / body.nodes.size();
  }
  return centres;
}

/// A count (bytes or doubles) as MPI's int, refused above it
int int_count(std::size_t count, const char* what)
{
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error(std::string(what) + ": " + std::to_string(count) +
                             " items from one rank, above MPI's int count");
  return static_cast<int>(count);
}

/// Offsets of consecutive blocks of the given sizes, refusing a total above
/// MPI's int count
std::vector<int> int_offsets(std::span<const int> counts, const char* what)
{
  constexpr std::size_t limit = std::numeric_limits<int>::max();
  std::vector<int> offsets(counts.size() + 1, 0);
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r)
  {
    total += counts[r];
    if (total > limit)
      throw std::runtime_error(std::string(what) + ": " +
                               std::to_string(total) +
                               " items in all, above MPI's int count");
    offsets[r + 1] = static_cast<int>(total);
  }
  return offsets;
}
} // namespace

Ownership::Ownership(MPI_Comm comm, bodies::BodySet& bodies) : _comm(comm)
{
  MPI_Comm_rank(comm, &_rank);
  MPI_Comm_size(comm, &_size);
  if (_size == 1)
    return;
  const int nb = bodies.num_bodies();
  if (_size > nb)
    throw std::invalid_argument(
        std::to_string(_size) + " MPI ranks for " + std::to_string(nb) +
        " bodies: --ranks must be between 1 and the number of bodies");
  // Centres of the reference configuration: every rank computes the same
  // split without messages.
  std::vector<double> weights(nb);
  for (int b = 0; b < nb; ++b)
    weights[b] = bodies.body(b).num_dofs();
  assign(partition_bodies(body_centres(bodies, bodies.reference_coordinates()),
                          weights, _size),
         bodies);
  bodies.set_owned(_owned);
}

void Ownership::assign(std::vector<int> body_rank, bodies::BodySet& bodies)
{
  const int nb = bodies.num_bodies();
  _body_rank = std::move(body_rank);
  _owned.assign(nb, 0);
  for (int b = 0; b < nb; ++b)
    _owned[b] = _body_rank[b] == _rank;
  // A rank stores its own bodies, every boundary and every rigid body
  // (moved by every rank); the other interiors share one NaN entry.
  bodies.keep_storage(_owned);
  _unstored = bodies.unstored_node();
  _node_owned.assign(bodies.num_dofs() / 2, 0);
  _owner_body_counts.assign(_size, 0);
  _owner_node_counts.assign(_size, 0);
  for (int b = 0; b < nb; ++b)
  {
    const bodies::Body& body = bodies.body(b);
    ++_owner_body_counts[_body_rank[b]];
    _owner_node_counts[_body_rank[b]] += body.nodes.size();
    if (_owned[b])
      for (std::int32_t node : body.nodes)
        _node_owned[node] = 1;
  }
  std::vector<int> next(_size, 0); // rank r's bodies start after r - 1's
  for (int r = 1; r < _size; ++r)
    next[r] = next[r - 1] + _owner_body_counts[r - 1];
  _bodies_by_owner.resize(nb);
  for (int b = 0; b < nb; ++b)
    _bodies_by_owner[next[_body_rank[b]]++] = b;
  _boundary_nodes = nodes_by_owner(
      bodies, [&](int b, std::size_t k)
      { return bodies.rigid(b) || bodies.body(b).segment_from[k] >= 0; });
}

template <typename Take>
Ownership::NodesByOwner Ownership::nodes_by_owner(const bodies::BodySet& bodies,
                                                  Take&& take) const
{
  std::vector<std::vector<int>> bodies_of(_size);
  for (int b = 0; b < bodies.num_bodies(); ++b)
    bodies_of[_body_rank[b]].push_back(b);
  NodesByOwner list;
  list.counts.assign(_size, 0);
  list.offsets.assign(_size + 1, 0);
  for (int r = 0; r < _size; ++r)
  {
    for (int b : bodies_of[r])
    {
      const std::vector<std::int32_t>& nodes = bodies.body(b).nodes;
      for (std::size_t k = 0; k < nodes.size(); ++k)
        if (take(b, k))
          list.nodes.push_back(nodes[k]);
    }
    const std::size_t end = 2 * list.nodes.size();
    if (end > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error("Ownership: " + std::to_string(end) +
                               " entries to share, above MPI's int count");
    list.offsets[r + 1] = static_cast<int>(end);
    list.counts[r] = list.offsets[r + 1] - list.offsets[r];
  }
  return list;
}

std::vector<int> Ownership::drifted_split(
    const bodies::BodySet& bodies, std::span<const double> x,
    std::span<const double> weights, std::span<const std::array<int, 2>> links,
    double tolerance) const
{
  if (_size == 1)
    return {};
  // One owner computes each centre: the sum is its value, bit for bit.
  std::vector<double> centres = body_centres(bodies, x, _owned);
  sum(centres);
  std::vector<int> fresh = partition_bodies(centres, weights, _size);
  if (!split_has_drifted(_body_rank, fresh, _size, weights, links, tolerance))
    return {};
  return fresh;
}

void Ownership::move_to(std::vector<int> split, bodies::BodySet& bodies,
                        std::span<std::vector<double>* const> vectors)
{
  if (split.size() != _body_rank.size())
    throw std::invalid_argument("Ownership::move_to: a rank for each body");
  // The moving bodies' entries (their interiors are their old owners'
  // only): displacement, reference coordinates, then the given vectors
  auto entries = [&](int b, auto&& visit)
  {
    std::vector<std::span<double>> all = {
        bodies.displacement(), bodies.stored_reference_coordinates()};
    for (std::vector<double>* v : vectors)
      if (!v->empty())
        all.emplace_back(*v);
    for (const std::span<double> v : all)
      for (const std::int32_t node : bodies.body(b).nodes)
        for (int c = 0; c < 2; ++c)
          visit(v[2 * node + c]);
  };
  const int nb = bodies.num_bodies();
  // With them, their cell lists (a rigid body's are on every rank)
  std::vector<std::vector<double>> to_rank(_size);
  std::vector<std::vector<std::int32_t>> lists_to_rank(_size);
  for (int b = 0; b < nb; ++b)
    if (_body_rank[b] == _rank && split[b] != _rank)
    {
      entries(b, [&](double x) { to_rank[split[b]].push_back(x); });
      if (!bodies.rigid(b))
      {
        const std::vector<std::int32_t> lists = bodies.cell_lists(b);
        std::vector<std::int32_t>& out = lists_to_rank[split[b]];
        out.insert(out.end(), lists.begin(), lists.end());
      }
    }
  // Received in the senders' rank order, each sender's bodies in order
  const std::vector<double> in = exchange_items(to_rank);
  const std::vector<std::int32_t> lists_in = exchange_items(lists_to_rank);
  const std::vector<int> before = _body_rank;
  for (int b = 0; b < nb; ++b)
    _moved += split[b] != before[b];
  ++_rebalances;
  assign(std::move(split), bodies);
  for (std::vector<double>* v : vectors)
    if (!v->empty())
      bodies.remap(*v);
  std::size_t k = 0, l = 0;
  for (int r = 0; r < _size; ++r)
    for (int b = 0; b < nb; ++b)
      if (before[b] == r && r != _rank && _body_rank[b] == _rank)
      {
        entries(b, [&](double& x) { x = in[k++]; });
        if (!bodies.rigid(b))
          l += bodies.take_cell_lists(b, std::span(lists_in).subspan(l));
      }
  if (k != in.size() || l != lists_in.size())
    throw std::logic_error("Ownership::move_to: " + std::to_string(in.size()) +
                           " entries and " + std::to_string(lists_in.size()) +
                           " list entries received, " + std::to_string(k) +
                           " and " + std::to_string(l) + " expected");
  // The arriving bodies' masses from their reference coordinates and
  // cells, now here
  bodies.set_owned(_owned);
}

std::vector<double>
Ownership::gather_to_root(const bodies::BodySet& bodies,
                          std::span<const double> stored) const
{
  if (_size == 1)
    return {stored.begin(), stored.end()};
  std::vector<int> counts(_size);
  for (int r = 0; r < _size; ++r)
    counts[r] =
        int_count(2 * _owner_node_counts[r], "Ownership::gather_to_root");
  const std::vector<int> offsets =
      int_offsets(counts, "Ownership::gather_to_root");
  // Each rank's bodies in order, each body's nodes in order
  std::vector<double> mine;
  mine.reserve(counts[_rank]);
  int begin = 0;
  for (int r = 0; r < _rank; ++r)
    begin += _owner_body_counts[r];
  for (int i = begin; i < begin + _owner_body_counts[_rank]; ++i)
    for (const std::int32_t node : bodies.body(_bodies_by_owner[i]).nodes)
      for (int c = 0; c < 2; ++c)
        mine.push_back(stored[2 * node + c]);
  std::vector<double> all(_rank == 0 ? offsets.back() : 0);
  MPI_Gatherv(mine.data(), counts[_rank], MPI_DOUBLE, all.data(), counts.data(),
              offsets.data(), MPI_DOUBLE, 0, _comm);
  if (_rank != 0)
  {
    _bytes += mine.size() * sizeof(double);
    ++_calls;
    return {};
  }
  ++_calls;
  std::vector<double> global(bodies.num_global_dofs());
  std::size_t k = 0;
  for (const int b : _bodies_by_owner)
    for (const std::int32_t g : bodies.body(b).global_nodes)
      for (int c = 0; c < 2; ++c)
        global[2 * g + c] = all[k++];
  return global;
}

void Ownership::share_by_body(std::span<double> values, int width) const
{
  if (_size == 1)
    return;
  std::vector<int> counts(_size), offsets(_size + 1, 0);
  for (int r = 0; r < _size; ++r)
  {
    counts[r] = width * _owner_body_counts[r];
    offsets[r + 1] = offsets[r] + counts[r];
  }
  std::vector<double> all(offsets.back());
  for (int k = offsets[_rank]; k < offsets[_rank + 1]; ++k)
    all[k] = values[width * _bodies_by_owner[k / width] + k % width];
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all.data(), counts.data(),
                 offsets.data(), MPI_DOUBLE, _comm);
  for (std::size_t k = 0; k < all.size(); ++k)
    values[width * _bodies_by_owner[k / width] + k % width] = all[k];
  _bytes += counts[_rank] * sizeof(double);
  ++_calls;
}

void Ownership::share_boundaries(std::span<double> global) const
{
  if (_size == 1)
    return;
  gather_nodes(global, _boundary_nodes);
  // What no rank writes: the other bodies' interiors' one entry
  constexpr double stale = std::numeric_limits<double>::quiet_NaN();
  global[2 * _unstored] = global[2 * _unstored + 1] = stale;
}

void Ownership::gather_nodes(std::span<double> global,
                             const NodesByOwner& list) const
{
  std::vector<double> all(list.offsets.back());
  for (int k = list.offsets[_rank]; k < list.offsets[_rank + 1]; ++k)
    all[k] = global[2 * list.nodes[k / 2] + k % 2];
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all.data(),
                 list.counts.data(), list.offsets.data(), MPI_DOUBLE, _comm);
  for (std::size_t k = 0; k < all.size(); ++k)
    global[2 * list.nodes[k / 2] + k % 2] = all[k];
  _bytes += list.counts[_rank] * sizeof(double);
  ++_calls;
}

void Ownership::share_nodes(std::span<double> global,
                            std::span<const std::int32_t> nodes) const
{
  if (_size == 1)
    return;
  std::vector<double> packed(2 * nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int c = 0; c < 2; ++c)
      packed[2 * k + c] = global[2 * nodes[k] + c];
  sum(packed);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int c = 0; c < 2; ++c)
      global[2 * nodes[k] + c] = packed[2 * k + c];
}

void Ownership::sum(std::span<double> values) const
{
  reduce(values, MPI_SUM);
}

void Ownership::sum_to_root(std::span<double> values) const
{
  if (_size == 1)
    return;
  MPI_Reduce(_rank == 0 ? MPI_IN_PLACE : values.data(), values.data(),
             static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, 0, _comm);
  if (_rank != 0)
    _bytes += values.size() * sizeof(double);
  ++_calls;
}

void Ownership::max(std::span<double> values) const
{
  reduce(values, MPI_MAX);
}

void Ownership::reduce(std::span<double> values, MPI_Op op) const
{
  if (_size == 1)
    return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                MPI_DOUBLE, op, _comm);
  _bytes += values.size() * sizeof(double);
  ++_calls;
}

std::vector<std::byte> Ownership::exchange_bytes(
    std::span<const std::span<const std::byte>> to_rank) const
{
  if (static_cast<int>(to_rank.size()) != _size)
    throw std::invalid_argument("Ownership::exchange: one list per rank");
  std::vector<int> send_counts(_size), receive_counts(_size);
  std::vector<std::byte> out;
  for (int r = 0; r < _size; ++r)
  {
    send_counts[r] = int_count(to_rank[r].size(), "Ownership::exchange");
    out.insert(out.end(), to_rank[r].begin(), to_rank[r].end());
  }
  const std::vector<int> send_offsets =
      int_offsets(send_counts, "Ownership::exchange (sent)");
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1,
               MPI_INT, _comm);
  const std::vector<int> receive_offsets =
      int_offsets(receive_counts, "Ownership::exchange (received)");
  std::vector<std::byte> in(receive_offsets.back());
  MPI_Alltoallv(out.data(), send_counts.data(), send_offsets.data(), MPI_BYTE,
                in.data(), receive_counts.data(), receive_offsets.data(),
                MPI_BYTE, _comm);
  // What leaves this rank (its own share stays)
  _bytes += _size * sizeof(int) + out.size() - to_rank[_rank].size();
  _calls += 2;
  return in;
}

std::vector<std::byte>
Ownership::gather_bytes(std::span<const std::byte> local) const
{
  // (not reached: 1,000 disks gather ~35 MB per step)
  const int n = int_count(local.size(), "Ownership::gather");
  std::vector<int> counts(_size);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, _comm);
  const std::vector<int> offsets = int_offsets(counts, "Ownership::gather");
  std::vector<std::byte> all(offsets.back());
  MPI_Allgatherv(local.data(), n, MPI_BYTE, all.data(), counts.data(),
                 offsets.data(), MPI_BYTE, _comm);
  _bytes += sizeof(int) + local.size();
  _calls += 2;
  return all;
}

} // namespace softpack::parallel
