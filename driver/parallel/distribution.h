#pragma once

#include "body_index_map.h"
#include "communicator.h"
#include "scatterer.h"
#include <bodies/BodySet.h>
#include <mpi.h>
#include <vector>

namespace softpack::parallel
{

/// The bodies of a run over MPI ranks (docs/mpi_design.md): the ranks
/// (Communicator), which rank owns which body (BodyIndexMap) and the
/// exchanges of the owners' entries (Scatterer). The body set it was built
/// on keeps its local bodies' entries, every boundary and every rigid body
/// (BodySet::keep_storage), and computes its local bodies only
/// (BodySet::set_local); the per-body results the rest of a step needs
/// everywhere go through the scatterer. A rebalance moves bodies between
/// ranks (rebalance.h).
///
/// The default object is serial: one rank owning every body, every
/// exchange a no-op (no MPI call at all).
class Distribution
{
public:
  /// One rank, every body its own.
  Distribution() = default;
  /// The bodies split over the ranks of `comm` by recursive coordinate
  /// bisection of their reference centres, weighted by their DOFs
  /// (partition_bodies); restricts `bodies` to this rank's share when there
  /// are several ranks.
  /// @throws std::invalid_argument if comm has more ranks than bodies
  Distribution(MPI_Comm comm, bodies::BodySet& bodies);

  /// Whether there is more than one rank
  bool distributed() const { return _comm.distributed(); }
  const Communicator& comm() const { return _comm; }
  const BodyIndexMap& index_map() const { return _map; }
  const Scatterer& scatterer() const { return _scatter; }

  /// Give body b to rank body_rank[b]: the map, the scatterer and the
  /// storage of `bodies` (BodySet::keep_storage) follow; the caller makes
  /// the new local bodies local (BodySet::set_local: their masses) once
  /// their entries are in place (move_bodies).
  void assign(std::vector<int> body_rank, bodies::BodySet& bodies);
  /// Count a rebalance that gave `moved` bodies to another rank
  void count_rebalance(long moved)
  {
    ++_rebalances;
    _moved += moved;
  }
  /// Rebalances done, and the bodies they gave to another rank
  int rebalances() const { return _rebalances; }
  long bodies_moved() const { return _moved; }

private:
  Communicator _comm;
  BodyIndexMap _map;
  Scatterer _scatter;
  int _rebalances = 0;
  long _moved = 0;
};

} // namespace softpack::parallel
