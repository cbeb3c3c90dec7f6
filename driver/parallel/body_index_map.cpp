#include "body_index_map.h"

namespace softpack::parallel
{

BodyIndexMap::BodyIndexMap(std::vector<int> body_rank, int rank, int size)
    : _rank(rank), _size(size), _body_rank(std::move(body_rank))
{
  const int nb = static_cast<int>(_body_rank.size());
  _counts.assign(_size, 0);
  for (int b = 0; b < nb; ++b)
    ++_counts[_body_rank[b]];
  _first.assign(_size, 0); // rank r's bodies start after r - 1's
  for (int r = 1; r < _size; ++r)
    _first[r] = _first[r - 1] + _counts[r - 1];
  std::vector<int> next = _first;
  _bodies_by_owner.resize(nb);
  for (int b = 0; b < nb; ++b)
    _bodies_by_owner[next[_body_rank[b]]++] = b;
}

std::vector<int> BodyIndexMap::local_bodies() const
{
  std::vector<int> local;
  for (int b = 0; b < static_cast<int>(_body_rank.size()); ++b)
    if (_body_rank[b] == _rank)
      local.push_back(b);
  return local;
}

std::vector<char> BodyIndexMap::local_flags() const
{
  std::vector<char> flags(_body_rank.size(), 0);
  for (std::size_t b = 0; b < flags.size(); ++b)
    flags[b] = _body_rank[b] == _rank;
  return flags;
}

} // namespace softpack::parallel
