#include "geometry_broadcast.h"

#include <algorithm>
#include <cstdint>
#include <span>

namespace softpack::parallel
{
namespace
{
/// Broadcast from rank 0 a buffer of any size (MPI counts are ints: sent
/// in pieces of at most 1 GiB)
template <typename T> void broadcast_bytes(MPI_Comm comm, std::span<T> v)
{
  constexpr std::size_t piece = std::size_t(1) << 30;
  auto* bytes = reinterpret_cast<char*>(v.data());
  for (std::size_t at = 0; at < v.size_bytes(); at += piece)
    MPI_Bcast(bytes + at,
              static_cast<int>(std::min(piece, v.size_bytes() - at)), MPI_BYTE,
              0, comm);
}
} // namespace

void broadcast_geometry(MPI_Comm comm, bodies::BodyGeometry& geometry)
{
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (size == 1)
    return;
  std::int64_t counts[3] = {geometry.num_nodes(),
                            static_cast<std::int64_t>(geometry.cells.size()),
                            geometry.dim};
  MPI_Bcast(counts, 3, MPI_INT64_T, 0, comm);
  geometry.dim = static_cast<int>(counts[2]);
  geometry.x.resize(geometry.dim * counts[0]);
  geometry.node_input.resize(counts[0]);
  geometry.cells.resize(counts[1]);
  geometry.cell_body.resize(counts[1]);
  broadcast_bytes(comm, std::span(geometry.x));
  broadcast_bytes(comm, std::span(geometry.node_input));
  broadcast_bytes(comm, std::span(geometry.cells));
  broadcast_bytes(comm, std::span(geometry.cell_body));
}

} // namespace softpack::parallel
