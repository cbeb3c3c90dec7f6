#pragma once

#include "body_index_map.h"
#include "communicator.h"
#include <bodies/BodySet.h>
#include <cstdint>
#include <span>
#include <vector>

namespace softpack::parallel
{

/// Moves the owners' entries of node vectors and per-body values to the
/// ranks that read them (docs/mpi_design.md): every body's boundary to
/// every rank once per step, chosen nodes (contact nodes), per-body output
/// values, and whole vectors to rank 0 at outputs. Each call gathers each
/// owner's entries (every rank sends its own), except share_nodes, a sum
/// with exactly one nonzero contributor per entry: either way a rank gets
/// the owner's bits.
///
/// The default scatterer is serial: every call a no-op.
class Scatterer
{
public:
  Scatterer() = default;
  /// @param[in] comm The ranks
  /// @param[in] map Which rank owns which body
  /// @param[in] bodies The bodies, their storage kept for `map`
  /// (BodySet::keep_storage)
  Scatterer(Communicator comm, const BodyIndexMap& map,
            const bodies::BodySet& bodies);

  /// A node vector of this rank's storage made global on rank 0 (what it
  /// writes at outputs: the state file, the fields), each body's entries
  /// from its owner (an MPI_Gatherv); empty on the other ranks. A
  /// collective.
  std::vector<double> gather_to_root(const bodies::BodySet& bodies,
                                     std::span<const double> stored) const;
  /// Per-cell values (`stride` per cell of the whole mesh, cell c's at
  /// stride * c: the internal variables) made global on rank 0, each
  /// cell's from its body's owner (an MPI_Gatherv); empty on the other
  /// ranks, a copy when serial. A collective.
  std::vector<double> gather_cells_to_root(const bodies::BodySet& bodies,
                                           std::span<const double> values,
                                           int stride) const;
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
  /// Make the given stored nodes' entries their owners' on every rank
  /// (boundary nodes: the same storage indices on every rank); they must
  /// be zero on the ranks that do not own them (a vector filled by owners
  /// only): the message is as small as the list.
  void share_nodes(std::span<double> global,
                   std::span<const std::int32_t> nodes) const;

private:
  /// Nodes listed by their owners' ranks (rank 0's first, each rank's in
  /// body order; the same list on every rank), and each rank's part of it
  /// in doubles (the bodies' dimension per node)
  struct NodesByOwner
  {
    std::vector<std::int32_t> nodes;
    std::vector<int> counts, offsets;
  };
  /// The boundary nodes and every rigid body's nodes, listed by owner
  NodesByOwner boundary_nodes(const bodies::BodySet& bodies) const;

  Communicator _comm;
  BodyIndexMap _map;
  /// The bodies' dimension: the entries per node of a node vector
  int _dim = 2;
  /// Each rank's count of nodes (of its bodies)
  std::vector<std::size_t> _owner_node_counts;
  /// The nodes share_boundaries makes current (storage indices: the same
  /// on every rank)
  NodesByOwner _boundary;
  /// The storage index of the interiors this rank does not store (NaN
  /// after share_boundaries)
  std::int32_t _unstored = -1;
};

} // namespace softpack::parallel
