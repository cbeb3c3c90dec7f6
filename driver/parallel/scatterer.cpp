#include "scatterer.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace softpack::parallel
{

Scatterer::Scatterer(Communicator comm, const BodyIndexMap& map,
                     const bodies::BodySet& bodies)
    : _comm(std::move(comm)), _map(map), _dim(bodies.dim()),
      _unstored(bodies.unstored_node())
{
  _owner_node_counts.assign(_map.size(), 0);
  for (int b = 0; b < bodies.num_bodies(); ++b)
    _owner_node_counts[_map.body_rank()[b]] += bodies.body(b).nodes.size();
  _boundary = boundary_nodes(bodies);
}

Scatterer::NodesByOwner
Scatterer::boundary_nodes(const bodies::BodySet& bodies) const
{
  const int size = _map.size();
  NodesByOwner list;
  list.counts.assign(size, 0);
  list.offsets.assign(size + 1, 0);
  const std::vector<int>& by_owner = _map.bodies_by_owner();
  for (int r = 0; r < size; ++r)
  {
    const int first = _map.first_of(r);
    for (int i = first; i < first + _map.owner_body_counts()[r]; ++i)
    {
      const int b = by_owner[i];
      const bodies::Body& body = bodies.body(b);
      if (bodies.rigid(b))
        list.nodes.insert(list.nodes.end(), body.nodes.begin(),
                          body.nodes.end());
      else
        for (const std::int32_t k : body.boundary_nodes)
          list.nodes.push_back(body.nodes[k]);
    }
    const std::size_t end = _dim * list.nodes.size();
    if (end > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error("Scatterer: " + std::to_string(end) +
                               " entries to share, above MPI's int count");
    list.offsets[r + 1] = static_cast<int>(end);
    list.counts[r] = list.offsets[r + 1] - list.offsets[r];
  }
  return list;
}

std::vector<double>
Scatterer::gather_to_root(const bodies::BodySet& bodies,
                          std::span<const double> stored) const
{
  if (!_comm.distributed())
    return {stored.begin(), stored.end()};
  const int rank = _comm.rank();
  std::vector<int> counts(_map.size());
  for (int r = 0; r < _map.size(); ++r)
    counts[r] =
        int_count(_dim * _owner_node_counts[r], "Scatterer::gather_to_root");
  // Each rank's bodies in order, each body's nodes in order
  std::vector<double> mine;
  mine.reserve(counts[rank]);
  const int first = _map.first_of(rank);
  for (int i = first; i < first + _map.owner_body_counts()[rank]; ++i)
    for (const std::int32_t node : bodies.body(_map.bodies_by_owner()[i]).nodes)
      for (int c = 0; c < _dim; ++c)
        mine.push_back(stored[_dim * node + c]);
  const std::vector<double> all = _comm.gather_to_root(mine, counts);
  if (rank != 0)
    return {};
  std::vector<double> global(bodies.num_global_dofs());
  std::size_t k = 0;
  for (const int b : _map.bodies_by_owner())
    for (const std::int32_t g : bodies.body(b).global_nodes)
      for (int c = 0; c < _dim; ++c)
        global[_dim * g + c] = all[k++];
  return global;
}

std::vector<double>
Scatterer::gather_cells_to_root(const bodies::BodySet& bodies,
                                std::span<const double> values,
                                int stride) const
{
  if (!_comm.distributed())
    return {values.begin(), values.end()};
  const int size = _map.size(), rank = _comm.rank();
  const std::vector<int>& owner = _map.body_rank();
  const std::span<const int> cell_body = bodies.cell_body();
  std::vector<int> counts(size, 0);
  for (const int b : cell_body)
    counts[owner[b]] += stride;
  std::vector<char> mine(owner.size());
  for (std::size_t b = 0; b < owner.size(); ++b)
    mine[b] = owner[b] == rank;
  const std::vector<double> all = _comm.gather_to_root(
      bodies::pick_cells(values, stride, cell_body, mine), counts);
  if (rank != 0)
    return {};
  // Rank r's block holds its bodies' cells in increasing order
  std::vector<int> at(size, 0);
  for (int r = 1; r < size; ++r)
    at[r] = at[r - 1] + counts[r - 1];
  std::vector<double> global(values.size());
  for (std::size_t c = 0; c < cell_body.size(); ++c)
  {
    int& k = at[owner[cell_body[c]]];
    std::copy_n(all.begin() + k, stride, global.begin() + c * stride);
    k += stride;
  }
  return global;
}

void Scatterer::share_by_body(std::span<double> values, int width) const
{
  if (!_comm.distributed())
    return;
  const int size = _map.size(), rank = _comm.rank();
  const std::vector<int>& by_owner = _map.bodies_by_owner();
  std::vector<int> counts(size), offsets(size + 1, 0);
  for (int r = 0; r < size; ++r)
  {
    counts[r] = width * _map.owner_body_counts()[r];
    offsets[r + 1] = offsets[r] + counts[r];
  }
  std::vector<double> all(offsets.back());
  for (int k = offsets[rank]; k < offsets[rank + 1]; ++k)
    all[k] = values[width * by_owner[k / width] + k % width];
  _comm.share_blocks(all, counts, offsets);
  for (std::size_t k = 0; k < all.size(); ++k)
    values[width * by_owner[k / width] + k % width] = all[k];
}

void Scatterer::share_boundaries(std::span<double> global) const
{
  if (!_comm.distributed())
    return;
  const int rank = _comm.rank();
  std::vector<double> all(_boundary.offsets.back());
  const int d = _dim;
  for (int k = _boundary.offsets[rank]; k < _boundary.offsets[rank + 1]; ++k)
    all[k] = global[d * _boundary.nodes[k / d] + k % d];
  _comm.share_blocks(all, _boundary.counts, _boundary.offsets);
  for (std::size_t k = 0; k < all.size(); ++k)
    global[d * _boundary.nodes[k / d] + k % d] = all[k];
  // What no rank writes: the other bodies' interiors' one entry
  constexpr double stale = std::numeric_limits<double>::quiet_NaN();
  for (int c = 0; c < d; ++c)
    global[d * _unstored + c] = stale;
}

void Scatterer::share_nodes(std::span<double> global,
                            std::span<const std::int32_t> nodes) const
{
  if (!_comm.distributed())
    return;
  const int d = _dim;
  std::vector<double> packed(d * nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int c = 0; c < d; ++c)
      packed[d * k + c] = global[d * nodes[k] + c];
  _comm.sum(packed);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int c = 0; c < d; ++c)
      global[d * nodes[k] + c] = packed[d * k + c];
}

} // namespace softpack::parallel
