#include "distribution.h"

#include "partition.h"
#include "rebalance.h"
#include <stdexcept>
#include <string>

namespace softpack::parallel
{

Distribution::Distribution(MPI_Comm comm, bodies::BodySet& bodies) : _comm(comm)
{
  const int size = _comm.size();
  if (size == 1)
    return;
  const int nb = bodies.num_bodies();
  if (size > nb)
    throw std::invalid_argument(
        std::to_string(size) + " MPI ranks for " + std::to_string(nb) +
        " bodies: --ranks must be between 1 and the number of bodies");
  // Centres of the reference configuration: every rank computes the same
  // split without messages.
  std::vector<double> weights(nb);
  std::vector<int> all(nb);
  for (int b = 0; b < nb; ++b)
  {
    weights[b] = bodies.body(b).num_dofs();
    all[b] = b;
  }
  assign(partition_bodies(
             body_centres(bodies, bodies.reference_coordinates(), all), weights,
             size, bodies.dim()),
         bodies);
  bodies.set_local(_map.local_bodies());
}

void Distribution::assign(std::vector<int> body_rank, bodies::BodySet& bodies)
{
  _map = BodyIndexMap(std::move(body_rank), _comm.rank(), _comm.size());
  // A rank stores its own bodies, every boundary and every rigid body
  // (moved by every rank); the other interiors share one NaN entry.
  bodies.keep_storage(_map.local_flags());
  _scatter = Scatterer(_comm, _map, bodies);
}

} // namespace softpack::parallel
