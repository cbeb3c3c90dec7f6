#include "DelassusMatrix.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

using namespace softpack::contact;

//-----------------------------------------------------------------------------
template <int D>
DelassusMatrixD<D>::DelassusMatrixD(std::size_t num_contacts)
    : _num_contacts(num_contacts), _diagonal(num_contacts, Block::Zero()),
      _offsets(num_contacts + 1, 0)
{
  if (num_contacts >
      static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw std::length_error("DelassusMatrix: too many contacts");
}
//-----------------------------------------------------------------------------
template <int D>
void DelassusMatrixD<D>::add_block(std::size_t a, std::size_t b,
                                   const Block& block)
{
  if (_finalized)
    throw std::logic_error("DelassusMatrix::add_block after finalize()");
  if (a >= _num_contacts or b >= _num_contacts)
  {
    throw std::out_of_range("DelassusMatrix::add_block: block (" +
                            std::to_string(a) + ", " + std::to_string(b) +
                            ") outside " + std::to_string(_num_contacts) +
                            " contacts");
  }
  if (a == b)
    _diagonal[a] += block;
  else
  {
    _pending.push_back(
        {static_cast<std::int32_t>(a), static_cast<std::int32_t>(b), block});
  }
}
//-----------------------------------------------------------------------------
template <int D>
void DelassusMatrixD<D>::add_rank_one(std::span<const std::int32_t> contacts,
                                      std::span<const Vector> g,
                                      double inverse_mass, bool add_diagonal,
                                      Reach reach)
{
  if (_finalized)
    throw std::logic_error("DelassusMatrix::add_rank_one after finalize()");
  if (g.size() != contacts.size())
    throw std::invalid_argument(
        "DelassusMatrix::add_rank_one: one g per contact");
  std::vector<char> seen(_num_contacts, 0);
  for (const std::int32_t c : contacts)
  {
    if (c < 0 or static_cast<std::size_t>(c) >= _num_contacts)
      throw std::out_of_range("DelassusMatrix::add_rank_one: contact " +
                              std::to_string(c) + " outside " +
                              std::to_string(_num_contacts) + " contacts");
    if (seen[c]++)
      throw std::invalid_argument("DelassusMatrix::add_rank_one: contact " +
                                  std::to_string(c) + " listed twice");
  }
  if (add_diagonal)
    for (std::size_t i = 0; i < contacts.size(); ++i)
      _diagonal[contacts[i]] += inverse_mass * g[i] * g[i].transpose();
  _terms.push_back({{contacts.begin(), contacts.end()},
                    {g.begin(), g.end()},
                    inverse_mass,
                    reach == Reach::local});
}
//-----------------------------------------------------------------------------
template <int D> void DelassusMatrixD<D>::index_terms()
{
  _term_offsets.clear();
  _term_entries.clear();
  if (_terms.empty())
    return;
  _term_offsets.assign(_num_contacts + 1, 0);
  for (const RankOne& t : _terms)
    for (const std::int32_t c : t.contacts)
      ++_term_offsets[c + 1];
  for (std::size_t a = 0; a < _num_contacts; ++a)
    _term_offsets[a + 1] += _term_offsets[a];
  _term_entries.resize(_term_offsets[_num_contacts]);
  std::vector<std::int32_t> next(_term_offsets.begin(),
                                 _term_offsets.end() - 1);
  for (std::size_t k = 0; k < _terms.size(); ++k)
    for (std::size_t i = 0; i < _terms[k].contacts.size(); ++i)
      _term_entries[next[_terms[k].contacts[i]]++] = {
          static_cast<std::int32_t>(k), static_cast<std::int32_t>(i)};
}
//-----------------------------------------------------------------------------
template <int D>
void DelassusMatrixD<D>::rank_one_sums(const double* r, double* sums) const
{
  for (std::size_t k = 0; k < _terms.size(); ++k)
  {
    const RankOne& t = _terms[k];
    double s = 0;
    for (std::size_t i = 0; i < t.contacts.size(); ++i)
      s += t.g[i].dot(contact_vector<D>(r, t.contacts[i]));
    sums[k] = s;
  }
}
//-----------------------------------------------------------------------------
template <int D> DelassusMatrixD<D> DelassusMatrixD<D>::expanded() const
{
  if (!_finalized)
    throw std::logic_error("DelassusMatrix::expanded before finalize()");
  DelassusMatrixD out(_num_contacts);
  out._diagonal = _diagonal;
  for (std::size_t a = 0; a < _num_contacts; ++a)
    for (std::int32_t k = _offsets[a]; k < _offsets[a + 1]; ++k)
      out.add_block(a, _columns[k], _blocks[k]);
  for (const RankOne& t : _terms)
    for (std::size_t i = 0; i < t.contacts.size(); ++i)
      for (std::size_t j = 0; j < t.contacts.size(); ++j)
        if (i != j)
          out.add_block(t.contacts[i], t.contacts[j],
                        t.inverse_mass * t.g[i] * t.g[j].transpose());
  out.finalize();
  return out;
}
//-----------------------------------------------------------------------------
template <int D>
void DelassusMatrixD<D>::bucket_by_row(std::vector<std::int32_t>& start,
                                       std::vector<std::int32_t>& by_row) const
{
  const std::size_t n = _num_contacts;
  start.assign(n + 1, 0);
  for (const Contribution& c : _pending)
    ++start[c.row + 1];
  for (std::size_t a = 0; a < n; ++a)
    start[a + 1] += start[a];
  by_row.resize(_pending.size());
  std::vector<std::int32_t> next(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < _pending.size(); ++k)
    by_row[next[_pending[k].row]++] = static_cast<std::int32_t>(k);
}
//-----------------------------------------------------------------------------
template <int D> void DelassusMatrixD<D>::finalize()
{
  if (_finalized)
    return;
  // Bucket by row (stable, linear); then, row by row on all cores, order
  // each row's contributions by column (ties in the order they came, so a
  // block's contributions are summed in that order: the same bits on any
  // number of threads) and merge them. A global sort of ~10^5
  // contributions per time step cost more than the blocks themselves, and
  // a serial std::stable_sort per row (a buffer allocated for each) was
  // ~7 % of a crowded step's time.
  const std::size_t n = _num_contacts;
  std::vector<std::int32_t> start, by_row;
  bucket_by_row(start, by_row);
  const auto rows = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 64) if (n >= 256)
  for (std::int64_t a = 0; a < rows; ++a)
  {
    std::sort(by_row.begin() + start[a], by_row.begin() + start[a + 1],
              [&](std::int32_t x, std::int32_t y)
              {
                const std::int32_t cx = _pending[x].col, cy = _pending[y].col;
                return cx < cy or (cx == cy and x < y);
              });
    std::int32_t distinct = 0;
    for (std::int32_t k = start[a]; k < start[a + 1]; ++k)
      distinct += k == start[a] or
                  _pending[by_row[k]].col != _pending[by_row[k - 1]].col;
    _offsets[a + 1] = distinct;
  }
  _offsets[0] = 0;
  for (std::size_t a = 0; a < n; ++a)
    _offsets[a + 1] += _offsets[a];
  _columns.resize(_offsets[n]);
  _blocks.resize(_offsets[n]);
#pragma omp parallel for schedule(dynamic, 64) if (n >= 256)
  for (std::int64_t a = 0; a < rows; ++a)
  {
    std::int32_t out = _offsets[a] - 1;
    for (std::int32_t k = start[a]; k < start[a + 1]; ++k)
    {
      const Contribution& c = _pending[by_row[k]];
      if (k == start[a] or c.col != _columns[out])
      {
        _columns[++out] = c.col;
        _blocks[out] = c.block;
      }
      else
        _blocks[out] += c.block;
    }
  }
  _pending.clear();
  _pending.shrink_to_fit();
  index_terms();
  _finalized = true;
}
//-----------------------------------------------------------------------------
template <int D>
DelassusMatrixD<D>
DelassusMatrixD<D>::renumbered(std::span<const std::int32_t> order) const
{
  if (!_finalized or order.size() != _num_contacts)
    throw std::invalid_argument(
        "DelassusMatrix::renumbered: needs a finalized operator and one "
        "new place per contact");
  std::vector<std::int32_t> position(_num_contacts, -1);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    const std::int32_t a = order[i];
    if (a < 0 or static_cast<std::size_t>(a) >= _num_contacts or
        position[a] >= 0)
      throw std::invalid_argument(
          "DelassusMatrix::renumbered: order is not a permutation");
    position[a] = static_cast<std::int32_t>(i);
  }
  DelassusMatrixD out(_num_contacts);
  out._columns.reserve(_columns.size());
  out._blocks.reserve(_blocks.size());
  for (std::size_t i = 0; i < _num_contacts; ++i)
  {
    const std::int32_t a = order[i];
    out._diagonal[i] = _diagonal[a];
    for (std::int32_t k = _offsets[a]; k < _offsets[a + 1]; ++k)
    {
      out._columns.push_back(position[_columns[k]]);
      out._blocks.push_back(_blocks[k]);
    }
    out._offsets[i + 1] = static_cast<std::int32_t>(out._columns.size());
  }
  out._terms = _terms;
  for (RankOne& t : out._terms)
    for (std::int32_t& c : t.contacts)
      c = position[c];
  out.index_terms();
  out._finalized = true;
  return out;
}
//-----------------------------------------------------------------------------
template <int D>
void DelassusMatrixD<D>::multiply_add(std::span<const double> r,
                                      std::span<double> u) const
{
  if (r.size() != D * _num_contacts or u.size() != D * _num_contacts)
    throw std::invalid_argument("DelassusMatrix::multiply_add: wrong sizes");
  std::vector<double> sums(_terms.size());
  rank_one_sums(r.data(), sums.data());
  const double* s = _terms.empty() ? nullptr : sums.data();
  for (std::size_t a = 0; a < _num_contacts; ++a)
  {
    const Vector ua = row_product(a, r.data(), s);
    for (int j = 0; j < D; ++j)
      u[D * a + j] += ua[j];
  }
}
//-----------------------------------------------------------------------------
template class softpack::contact::DelassusMatrixD<2>;
template class softpack::contact::DelassusMatrixD<3>;
//-----------------------------------------------------------------------------
