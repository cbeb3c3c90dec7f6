#pragma once

#include <bodies/body_geometry.h>
#include <mpi.h>

namespace softpack::parallel
{

/// Send rank 0's body geometry to every rank of `comm` (a collective;
/// the other ranks' `geometry` is replaced). The mesh is read once, by
/// rank 0: dolfinx's mesh construction needs several times the geometry
/// for a moment (~250 MB at 1,000 disks of the paper's mesh, against
/// ~26 MB of arrays), which the other ranks then never hold
/// (docs/mpi_design.md). No MPI call on one rank.
void broadcast_geometry(MPI_Comm comm, bodies::BodyGeometry& geometry);

} // namespace softpack::parallel
