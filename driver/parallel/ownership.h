#pragma once

#include <array>
#include <bodies/BodySet.h>
#include <cstddef>
#include <cstring>
#include <mpi.h>
#include <span>
#include <type_traits>
#include <vector>

namespace softpack::parallel
{

/// Which MPI rank owns each body, and the collectives that make the owners'
/// per-body results known to every rank (docs/mpi_design.md).
///
/// A rank stores the node vectors' entries of its own bodies, of every
/// body's boundary and of every rigid body (BodySet::keep_storage); it
/// assembles, factorizes and computes the compliance of its own bodies
/// only, and the per-body results that the rest of the step needs
/// everywhere are exchanged through the calls below: the velocity at the
/// bodies' boundaries once per step (share_boundaries; the interiors stay
/// with their owners: rank 0 receives them at outputs, gather_to_root, and
/// a body's new owner at a rebalance, move_to), free velocities at
/// contact nodes, Delassus blocks, per-body output values (share_by_body).
/// gather_to_root, share_boundaries and share_by_body gather each owner's
/// entries (each rank sends its own); the other exchanges are sums with
/// exactly one nonzero contributor per entry. Either way a rank gets the
/// owner's bits.
///
/// The default object is serial: one rank owning every body, and every
/// call a no-op (no MPI call at all).
class Ownership
{
public:
  /// One rank, every body owned.
  Ownership() = default;
  /// The bodies split over the ranks of `comm` by recursive coordinate
  /// bisection of their reference centres, weighted by their DOFs
  /// (partition_bodies); restricts `bodies` to its owned ones
  /// (BodySet::set_owned) and its storage to them (BodySet::keep_storage)
  /// when there are several ranks.
  /// @throws std::invalid_argument if comm has more ranks than bodies
  Ownership(MPI_Comm comm, bodies::BodySet& bodies);

  /// A new split of the bodies, by recursive coordinate bisection of
  /// their current centres with the given weights, when the split in force
  /// has drifted from it (split_has_drifted: uneven work, or many more
  /// contacts cut between ranks); else empty. Every rank decides alike
  /// from the same data (the centres are summed over the ranks, each from
  /// its owner: x is read at the owned bodies' nodes only).
  /// @param[in] x Current node coordinates (the storage, interleaved)
  /// @param[in] weights Work of each body, > 0
  /// @param[in] links The body pairs of the contacts between bodies
  /// @param[in] tolerance Relative drift allowed (e.g. 0.1)
  /// @return The rank of each body, or empty
  std::vector<int> drifted_split(const bodies::BodySet& bodies,
                                 std::span<const double> x,
                                 std::span<const double> weights,
                                 std::span<const std::array<int, 2>> links,
                                 double tolerance) const;
  /// Give the bodies to the ranks of a drifted_split (counted as a
  /// rebalance): each body that changes rank sends its entries of the
  /// displacement, the reference coordinates and the given node vectors
  /// (the empty ones skipped), and its cell lists (BodySet::cell_lists),
  /// from its old owner to its new one (two all-to-alls: its interior and
  /// cells are its old owner's only); `bodies` is
  /// restricted to this rank's (BodySet::set_owned) and its storage to
  /// them (BodySet::keep_storage), and the given vectors remapped to it.
  void move_to(std::vector<int> split, bodies::BodySet& bodies,
               std::span<std::vector<double>* const> vectors);
  /// Rebalances done, and the bodies they gave to another rank
  int rebalances() const { return _rebalances; }
  long bodies_moved() const { return _moved; }

  /// Whether there is more than one rank
  bool distributed() const { return _size > 1; }
  int rank() const { return _rank; }
  /// The ranks (MPI_COMM_SELF when serial)
  MPI_Comm comm() const { return _comm; }
  int size() const { return _size; }
  /// Whether this rank owns body b
  bool owns(int b) const { return _size == 1 || _body_rank[b] == _rank; }
  /// 1 for each owned body (empty when serial: all)
  const std::vector<char>& owned() const { return _owned; }
  /// The rank of each body (empty when serial)
  const std::vector<int>& body_rank() const { return _body_rank; }

  /// A node vector of this rank's storage made global on rank 0 (what it
  /// writes at outputs: the state file, the fields), each body's entries
  /// from its owner (an MPI_Gatherv); empty on the other ranks. A
  /// collective.
  std::vector<double> gather_to_root(const bodies::BodySet& bodies,
                                     std::span<const double> stored) const;
  /// Make per-body values (`width` per body, body b's at width * b) those
  /// of each body's owner on every rank: a rank computes its own bodies'
  /// (energies, stresses) and sends only those
  void share_by_body(std::span<double> values, int width) const;
  /// Make the entries read between outputs current on every rank: the
  /// boundary nodes of every body (detection, the contact operator, areas,
  /// overlaps) and every node of a rigid body (moved by every rank), as
  /// their owners hold them. The other ranks' bodies' interior entries
  /// become NaN: a read of one shows in the results instead of passing for
  /// a value.
  void share_boundaries(std::span<double> global) const;
  /// 1 for each stored node of an owned body (empty when serial: all)
  const std::vector<char>& node_owned() const { return _node_owned; }
  /// Make the given stored nodes' entries their owners' on every rank
  /// (boundary nodes: the same storage indices on every rank);
  /// they must be zero on the ranks that do not own them (a vector filled
  /// by owners only): the message is as small as the list.
  void share_nodes(std::span<double> global,
                   std::span<const std::int32_t> nodes) const;
  /// Sum over ranks, in place.
  void sum(std::span<double> values) const;
  /// Sum over ranks onto rank 0, in place (the other ranks' values are
  /// left as they are): per-cell values of which each rank computed its
  /// own bodies', the others zero (exact: x + 0 = x)
  void sum_to_root(std::span<double> values) const;
  /// Largest over ranks, in place (exact: every rank gets the same bits).
  void max(std::span<double> values) const;
  /// All ranks' vectors concatenated in rank order, on every rank.
  std::vector<double> gather(std::span<const double> local) const
  {
    return gather_items<double>(local);
  }
  /// gather() of plain records (sent as their bytes: every rank runs the
  /// same build)
  template <typename T>
  std::vector<T> gather_items(std::span<const T> local) const
  {
    static_assert(std::is_trivially_copyable_v<T>);
    if (_size == 1)
      return {local.begin(), local.end()};
    const std::vector<std::byte> all = gather_bytes(std::as_bytes(local));
    std::vector<T> items(all.size() / sizeof(T));
    std::memcpy(items.data(), all.data(), all.size());
    return items;
  }

  /// Send each rank r the records to_rank[r] (size(): one list per rank);
  /// receive what every rank sent this one, concatenated in rank order.
  template <typename T>
  std::vector<T>
  exchange_items(const std::vector<std::vector<T>>& to_rank) const
  {
    static_assert(std::is_trivially_copyable_v<T>);
    if (_size == 1)
      return to_rank.empty() ? std::vector<T>{} : to_rank[0];
    std::vector<std::span<const std::byte>> out;
    for (const std::vector<T>& items : to_rank)
      out.push_back(std::as_bytes(std::span<const T>(items)));
    const std::vector<std::byte> in = exchange_bytes(out);
    std::vector<T> items(in.size() / sizeof(T));
    std::memcpy(items.data(), in.data(), in.size());
    return items;
  }

  /// Bytes this rank has handed to collectives so far (its send volume;
  /// what the network carries is of the same order per rank)
  std::size_t bytes_sent() const { return _bytes; }
  /// Collective calls so far
  std::size_t messages() const { return _calls; }

private:
  /// Nodes listed by their owners' ranks (rank 0's first, each rank's in
  /// body order; the same list on every rank), and each rank's part of it
  /// in doubles (2 per node): an allgatherv of each owner's entries makes
  /// them current everywhere, every rank sending its own part only and no
  /// arithmetic touching a value.
  struct NodesByOwner
  {
    std::vector<std::int32_t> nodes;
    std::vector<int> counts, offsets;
  };
  /// The nodes of every body that `take(body, local node)` accepts, listed
  /// by owner
  template <typename Take>
  NodesByOwner nodes_by_owner(const bodies::BodySet& bodies, Take&& take) const;
  /// Make the listed nodes' entries their owners' on every rank
  void gather_nodes(std::span<double> global, const NodesByOwner& list) const;
  /// Give body b to rank body_rank[b] and keep this rank's storage
  /// (BodySet::keep_storage); the caller restricts `bodies` to this rank's
  /// (BodySet::set_owned: their masses) once their entries are in place
  void assign(std::vector<int> body_rank, bodies::BodySet& bodies);
  /// An allreduce in place with `op`, counted
  void reduce(std::span<double> values, MPI_Op op) const;
  std::vector<std::byte> gather_bytes(std::span<const std::byte> local) const;
  std::vector<std::byte>
  exchange_bytes(std::span<const std::span<const std::byte>> to_rank) const;

  MPI_Comm _comm = MPI_COMM_SELF;
  int _rank = 0, _size = 1;
  std::vector<int> _body_rank;
  std::vector<char> _owned;
  /// The storage index of the interiors this rank does not store (NaN
  /// after share_boundaries)
  std::int32_t _unstored = -1;
  /// The nodes share_boundaries makes current (storage indices: the same
  /// on every rank)
  NodesByOwner _boundary_nodes;
  /// The bodies listed by owner (share_by_body, gather_to_root), and each
  /// rank's count of bodies and of their nodes
  std::vector<int> _bodies_by_owner, _owner_body_counts;
  std::vector<std::size_t> _owner_node_counts;
  std::vector<char> _node_owned;
  mutable std::size_t _bytes = 0, _calls = 0;
  int _rebalances = 0;
  long _moved = 0;
};

} // namespace softpack::parallel
