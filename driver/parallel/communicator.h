#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <mpi.h>
#include <span>
#include <type_traits>
#include <vector>

namespace softpack::parallel
{

/// The collectives a distributed run needs, over one MPI communicator, and
/// the traffic they made (docs/mpi_design.md). Copies share the count of
/// the traffic: they are the same communicator.
///
/// The default object is serial (MPI_COMM_SELF): every call returns its
/// input, with no MPI call at all.
class Communicator
{
public:
  /// One process, no MPI call.
  Communicator();
  explicit Communicator(MPI_Comm comm);

  /// Whether there is more than one rank
  bool distributed() const { return _size > 1; }
  int rank() const { return _rank; }
  int size() const { return _size; }
  /// The ranks (MPI_COMM_SELF when serial)
  MPI_Comm comm() const { return _comm; }

  /// Sum over ranks, in place.
  void sum(std::span<double> values) const;
  /// Sum over ranks onto rank 0, in place (the other ranks' values are
  /// left as they are): values of which each rank computed its own part,
  /// the others zero (exact: x + 0 = x)
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

  /// Each rank's block of `all` (block r at offsets[r], counts[r] entries)
  /// filled in by that rank, made whole on every rank (an allgatherv in
  /// place: every rank sends its own block only).
  void share_blocks(std::span<double> all, std::span<const int> counts,
                    std::span<const int> offsets) const;
  /// Every rank's `mine`, in rank order, on rank 0 (an MPI_Gatherv); empty
  /// on the other ranks.
  /// @param[in] counts Each rank's number of entries
  std::vector<double> gather_to_root(std::span<const double> mine,
                                     std::span<const int> counts) const;

  /// Bytes this rank has handed to collectives so far (its send volume;
  /// what the network carries is of the same order per rank)
  std::size_t bytes_sent() const { return _traffic->bytes; }
  /// Collective calls so far
  std::size_t messages() const { return _traffic->calls; }

private:
  struct Traffic
  {
    std::size_t bytes = 0, calls = 0;
  };
  /// An allreduce in place with `op`, counted
  void reduce(std::span<double> values, MPI_Op op) const;
  std::vector<std::byte> gather_bytes(std::span<const std::byte> local) const;
  std::vector<std::byte>
  exchange_bytes(std::span<const std::span<const std::byte>> to_rank) const;

  MPI_Comm _comm = MPI_COMM_SELF;
  int _rank = 0, _size = 1;
  std::shared_ptr<Traffic> _traffic;
};

/// A count (bytes or doubles) as MPI's int, refused above it
int int_count(std::size_t count, const char* what);
/// Offsets of consecutive blocks of the given sizes (counts.size() + 1 of
/// them), refusing a total above MPI's int count
std::vector<int> int_offsets(std::span<const int> counts, const char* what);

} // namespace softpack::parallel
