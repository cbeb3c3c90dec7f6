#include "communicator.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace softpack::parallel
{

int int_count(std::size_t count, const char* what)
{
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error(std::string(what) + ": " + std::to_string(count) +
                             " items from one rank, above MPI's int count");
  return static_cast<int>(count);
}

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

Communicator::Communicator() : _traffic(std::make_shared<Traffic>()) {}

Communicator::Communicator(MPI_Comm comm)
    : _comm(comm), _traffic(std::make_shared<Traffic>())
{
  MPI_Comm_rank(comm, &_rank);
  MPI_Comm_size(comm, &_size);
}

void Communicator::sum(std::span<double> values) const
{
  reduce(values, MPI_SUM);
}

void Communicator::sum_to_root(std::span<double> values) const
{
  if (_size == 1)
    return;
  MPI_Reduce(_rank == 0 ? MPI_IN_PLACE : values.data(), values.data(),
             static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, 0, _comm);
  if (_rank != 0)
    _traffic->bytes += values.size() * sizeof(double);
  ++_traffic->calls;
}

void Communicator::max(std::span<double> values) const
{
  reduce(values, MPI_MAX);
}

void Communicator::reduce(std::span<double> values, MPI_Op op) const
{
  if (_size == 1)
    return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                MPI_DOUBLE, op, _comm);
  _traffic->bytes += values.size() * sizeof(double);
  ++_traffic->calls;
}

void Communicator::share_blocks(std::span<double> all,
                                std::span<const int> counts,
                                std::span<const int> offsets) const
{
  if (_size == 1)
    return;
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all.data(), counts.data(),
                 offsets.data(), MPI_DOUBLE, _comm);
  _traffic->bytes += counts[_rank] * sizeof(double);
  ++_traffic->calls;
}

std::vector<double>
Communicator::gather_to_root(std::span<const double> mine,
                             std::span<const int> counts) const
{
  if (_size == 1)
    return {mine.begin(), mine.end()};
  const std::vector<int> offsets =
      int_offsets(counts, "Communicator::gather_to_root");
  std::vector<double> all(_rank == 0 ? offsets.back() : 0);
  MPI_Gatherv(mine.data(), counts[_rank], MPI_DOUBLE, all.data(), counts.data(),
              offsets.data(), MPI_DOUBLE, 0, _comm);
  if (_rank != 0)
    _traffic->bytes += mine.size() * sizeof(double);
  ++_traffic->calls;
  return all;
}

std::vector<std::byte> Communicator::exchange_bytes(
    std::span<const std::span<const std::byte>> to_rank) const
{
  if (static_cast<int>(to_rank.size()) != _size)
    throw std::invalid_argument("Communicator::exchange: one list per rank");
  std::vector<int> send_counts(_size), receive_counts(_size);
  std::vector<std::byte> out;
  for (int r = 0; r < _size; ++r)
  {
    send_counts[r] = int_count(to_rank[r].size(), "Communicator::exchange");
    out.insert(out.end(), to_rank[r].begin(), to_rank[r].end());
  }
  const std::vector<int> send_offsets =
      int_offsets(send_counts, "Communicator::exchange (sent)");
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1,
               MPI_INT, _comm);
  const std::vector<int> receive_offsets =
      int_offsets(receive_counts, "Communicator::exchange (received)");
  std::vector<std::byte> in(receive_offsets.back());
  MPI_Alltoallv(out.data(), send_counts.data(), send_offsets.data(), MPI_BYTE,
                in.data(), receive_counts.data(), receive_offsets.data(),
                MPI_BYTE, _comm);
  // What leaves this rank (its own share stays)
  _traffic->bytes += _size * sizeof(int) + out.size() - to_rank[_rank].size();
  _traffic->calls += 2;
  return in;
}

std::vector<std::byte>
Communicator::gather_bytes(std::span<const std::byte> local) const
{
  const int n = int_count(local.size(), "Communicator::gather");
  std::vector<int> counts(_size);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, _comm);
  const std::vector<int> offsets = int_offsets(counts, "Communicator::gather");
  std::vector<std::byte> all(offsets.back());
  MPI_Allgatherv(local.data(), n, MPI_BYTE, all.data(), counts.data(),
                 offsets.data(), MPI_BYTE, _comm);
  _traffic->bytes += sizeof(int) + local.size();
  _traffic->calls += 2;
  return all;
}

} // namespace softpack::parallel
