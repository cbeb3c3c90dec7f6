#pragma once

#include <vector>

namespace softpack::parallel
{

/// Which rank owns each body (docs/mpi_design.md): the bodies a rank
/// computes (its local bodies), and the bodies listed by owner, in which
/// order the owners' per-body entries travel (Scatterer).
///
/// The default map is serial: one rank owning every body.
class BodyIndexMap
{
public:
  /// One rank, every body its own
  BodyIndexMap() = default;
  /// @param[in] body_rank The rank of each body
  /// @param[in] rank This rank
  /// @param[in] size The number of ranks
  BodyIndexMap(std::vector<int> body_rank, int rank, int size);

  int rank() const { return _rank; }
  int size() const { return _size; }
  /// Whether this rank owns body b
  bool owns(int b) const { return _size == 1 || _body_rank[b] == _rank; }
  /// The rank of each body (empty when serial)
  const std::vector<int>& body_rank() const { return _body_rank; }
  /// This rank's bodies, in increasing order (BodySet::set_local)
  std::vector<int> local_bodies() const;
  /// 1 for each of this rank's bodies
  std::vector<char> local_flags() const;
  /// The bodies listed by owner: rank 0's first, each rank's in increasing
  /// order
  const std::vector<int>& bodies_by_owner() const { return _bodies_by_owner; }
  /// Each rank's number of bodies, and where its part of bodies_by_owner
  /// begins
  const std::vector<int>& owner_body_counts() const { return _counts; }
  int first_of(int rank) const { return _first[rank]; }

private:
  int _rank = 0, _size = 1;
  std::vector<int> _body_rank, _bodies_by_owner, _counts, _first;
};

} // namespace softpack::parallel
