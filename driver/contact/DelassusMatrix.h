#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace softpack::contact
{

/// The entries of contact a's D-vector in a vector of D per contact, as an
/// Eigen vector (a 2-vector built from its two entries, as the 2D solver
/// always did: the same operations, the same bits)
template <int D>
inline Eigen::Matrix<double, D, 1> contact_vector(const double* x,
                                                  std::size_t a)
{
  if constexpr (D == 2)
    return Eigen::Vector2d(x[2 * a], x[2 * a + 1]);
  else
    return Eigen::Vector3d(x[3 * a], x[3 * a + 1], x[3 * a + 2]);
}

/// Block-sparse Delassus operator \f$W = H^T \bar K^{-1} H\f$ of a contact
/// problem in D = 2 or 3 dimensions, stored as compressed rows of D x D
/// blocks (DelassusMatrix: 2D, DelassusMatrix3D: 3D).
///
/// Block \f$W_{ab}\f$ maps the impulse of contact \f$b\f$ to the relative
/// velocity of contact \f$a\f$, both in the local frame \f$(n, t)\f$
/// (2D) or \f$(n, t_1, t_2)\f$ (3D). Row
/// \f$a\f$ holds its diagonal block and the list of off-diagonal blocks
/// \f$(b, W_{ab})\f$, \f$b \ne a\f$, sorted by \f$b\f$ (but in a
/// renumbered() copy). Two contacts are
/// coupled only when they share a body, so the number of blocks per row is
/// small and a product \f$W r\f$ costs O(number of blocks).
///
/// Use: construct with the number of contacts, call add_block() for every
/// contribution (contributions to the same block are summed, as when a pair
/// of contacts shares two bodies), then finalize(). Every row must end up with
/// a diagonal block; a missing one is stored as zero and rejected by
/// validate() of the problem.
///
/// The solvers only use diagonal() and offdiagonal_product(), one block row
/// at a time. An "operator" form of W (products through the bodies'
/// compliances, $W r = H^T (ar K^{-1} (H r))$, with per-contact
/// updates of the body velocities) can offer the same two calls, so that the
/// NLGS sweep stays O(stored blocks or touched body DOFs) per sweep.
template <int D> class DelassusMatrixD
{
  static_assert(D == 2 or D == 3, "contact problems are 2D or 3D");

public:
  /// A block and a contact's vector
  using Block = Eigen::Matrix<double, D, D>;
  using Vector = Eigen::Matrix<double, D, 1>;

  /// Create an empty operator.
  /// @param[in] num_contacts Number of contacts (block rows and columns)
  explicit DelassusMatrixD(std::size_t num_contacts = 0);

  /// Add a contribution to a block (builder phase only).
  /// @param[in] a Row contact (the velocity)
  /// @param[in] b Column contact (the impulse)
  /// @param[in] block D x D block in (n, t...) order, added to \f$W_{ab}\f$
  /// @throws std::out_of_range if a or b is not a contact
  /// @throws std::logic_error after finalize()
  void add_block(std::size_t a, std::size_t b, const Block& block);

  /// Reserve room for contributions (builder phase).
  /// @param[in] num_blocks Expected number of add_block() calls
  void reserve(std::size_t num_blocks) { _pending.reserve(num_blocks); }

  /// Sort and merge the contributions into compressed block rows.
  void finalize();

  /// @return true once finalize() has been called
  bool finalized() const { return _finalized; }

  /// @return Number of contacts
  std::size_t num_contacts() const { return _num_contacts; }

  /// @return Number of stored off-diagonal blocks (all rows)
  std::size_t num_offdiagonal_blocks() const { return _columns.size(); }

  /// @param[in] a Contact index
  /// @return Diagonal block \f$W_{aa}\f$
  const Block& diagonal(std::size_t a) const { return _diagonal[a]; }

  /// @param[in] a Contact index
  /// @return Column (contact) indices of the off-diagonal blocks of row a
  std::span<const std::int32_t> row_columns(std::size_t a) const
  {
    return {_columns.data() + _offsets[a],
            static_cast<std::size_t>(_offsets[a + 1] - _offsets[a])};
  }

  /// @param[in] a Contact index
  /// @return Off-diagonal blocks of row a, in the order of row_columns()
  std::span<const Block> row_blocks(std::size_t a) const
  {
    return {_blocks.data() + _offsets[a],
            static_cast<std::size_t>(_offsets[a + 1] - _offsets[a])};
  }

  /// Off-diagonal part of block row a applied to r:
  /// \f$\sum_{b \ne a} W_{ab} r_b\f$.
  /// @param[in] a Contact index
  /// @param[in] r Reactions, D per contact in (n, t...) order
  /// @return The D-vector of the sum
  Vector offdiagonal_product(std::size_t a, const double* r) const
  {
    Vector sum = Vector::Zero();
    const std::int32_t end = _offsets[a + 1];
    for (std::int32_t k = _offsets[a]; k < end; ++k)
      sum += _blocks[k] *
             contact_vector<D>(r, static_cast<std::size_t>(_columns[k]));
    return sum;
  }

  /// Block row a applied to r: \f$\sum_b W_{ab} r_b\f$.
  /// @param[in] sums The rank-one terms' sums at r (rank_one_sums()); may
  /// be null when W has none
  Vector row_product(std::size_t a, const double* r,
                     const double* sums = nullptr) const
  {
    return _diagonal[a] * contact_vector<D>(r, a) +
           offdiagonal_product(a, r, sums);
  }

  /// A rank-one term of W, \f$m^{-1} G G^T\f$ over some contacts: the
  /// compliance of a servo unknown (a servo wall, a stress-controlled
  /// cell component) that every one of these contacts moves, contact c_i
  /// by \f$g_i\f$ (dynamics::WallCoupling). Its off-diagonal blocks
  /// \f$m^{-1} g_i g_j^T\f$ are never stored: a solver keeps the sum
  /// \f$s = \sum_j g_j \cdot r_{c_j}\f$ (rank_one_sums()) and row c_i
  /// reads \f$m^{-1} g_i (s - g_i \cdot r_{c_i})\f$, O(contacts) per sweep
  /// and in memory where the blocks cost their square.
  struct RankOne
  {
    std::vector<std::int32_t> contacts;
    std::vector<Vector> g;
    double inverse_mass = 0;
    /// Whether its contacts are near one another (one body's, and those
    /// W's blocks couple to them: a held set's term,
    /// FrictionlessCondensation), so that a split sweep may keep them on
    /// one side of its separator; a term spread over the packing (a servo
    /// unknown's) is in the separator (split_for_two_threads)
    bool local = false;
  };

  /// Where a rank-one term's contacts lie (RankOne::local)
  enum class Reach
  {
    spread,
    local
  };

  /// Add a rank-one term (builder phase). Its diagonal blocks
  /// \f$m^{-1} g_i g_i^T\f$ are added to W's diagonal now, after what
  /// add_block() gave them so far (unless `add_diagonal` is false: a
  /// diagonal that has them already).
  /// @throws std::out_of_range if a contact is not one, std::logic_error
  /// after finalize(), std::invalid_argument for a contact listed twice or
  /// sizes that differ
  void add_rank_one(std::span<const std::int32_t> contacts,
                    std::span<const Vector> g, double inverse_mass,
                    bool add_diagonal = true, Reach reach = Reach::spread);

  /// @return The rank-one terms
  std::span<const RankOne> rank_one_terms() const { return _terms; }

  /// Contact a's place in a rank-one term: the term and a's index in it
  struct TermEntry
  {
    std::int32_t term, index;
  };

  /// @return The rank-one terms contact a is in (finalized)
  std::span<const TermEntry> terms_of(std::size_t a) const
  {
    if (_term_offsets.empty())
      return {};
    return {_term_entries.data() + _term_offsets[a],
            static_cast<std::size_t>(_term_offsets[a + 1] - _term_offsets[a])};
  }

  /// Each rank-one term's sum \f$s_k = \sum_j g_{k,j} \cdot r_{c_j}\f$
  /// at r, written to sums (one per term)
  void rank_one_sums(const double* r, double* sums) const;

  /// After contact a's reaction changed by dr: its terms' sums updated
  void update_sums(std::size_t a, const Vector& dr, double* sums) const
  {
    for (const TermEntry& e : terms_of(a))
      sums[e.term] += _terms[e.term].g[e.index].dot(dr);
  }

  /// offdiagonal_product() and the rank-one terms' off-diagonal part,
  /// \f$\sum_{k \ni a} m_k^{-1} g_{k,a} (s_k - g_{k,a} \cdot r_a)\f$, with
  /// the terms' current sums (null: W has none; then it is
  /// offdiagonal_product(), the same bits)
  Vector offdiagonal_product(std::size_t a, const double* r,
                             const double* sums) const
  {
    Vector sum = offdiagonal_product(a, r);
    if (sums)
      add_rank_one_offdiagonal(a, r, sums, sum);
    return sum;
  }

  /// sum += the rank-one terms' off-diagonal part of row a (see
  /// offdiagonal_product()), term by term
  void add_rank_one_offdiagonal(std::size_t a, const double* r,
                                const double* sums, Vector& sum) const
  {
    for (const TermEntry& e : terms_of(a))
    {
      const RankOne& t = _terms[e.term];
      const Vector& g = t.g[e.index];
      sum +=
          (t.inverse_mass * (sums[e.term] - g.dot(contact_vector<D>(r, a)))) *
          g;
    }
  }

  /// After contact a's reaction changed by dr: \f$v_b \mathrel{+}= W_{ba}
  /// dr\f$ for each stored block of row a whose column b is below `kept`,
  /// with \f$W_{ba} = W_{ab}^T\f$ (W is symmetric, to the rounding of its
  /// blocks). Row a's own stream, so that a velocity-updated sweep
  /// (NlgsUpdate::velocity) reads each row once per change of its reaction.
  void scatter_change(std::size_t a, const Vector& dr, double* v,
                      std::size_t kept) const
  {
    const std::int32_t end = _offsets[a + 1];
    for (std::int32_t k = _offsets[a]; k < end; ++k)
    {
      const auto b = static_cast<std::size_t>(_columns[k]);
      if (b >= kept)
        continue;
      const Vector dv = _blocks[k].transpose() * dr;
      for (int j = 0; j < D; ++j)
        v[D * b + j] += dv[j];
    }
  }

  /// The same W with the rank-one terms' off-diagonal blocks stored as
  /// blocks (a file format or a dense check needs them; O(contacts^2) per
  /// term)
  DelassusMatrixD expanded() const;

  /// The same operator with its contacts renumbered: contact `order[i]`
  /// becomes contact i (in the rank-one terms too). Each row keeps its blocks
  /// in their order (sorted by the old numbers, so no longer by the new ones),
  /// so every product sums in the same order as before and gives the same bits.
  /// A solver that visits the rows in `order` then reads them one after the
  /// other.
  /// @param[in] order A permutation of the contacts, finalized operator
  /// @throws std::invalid_argument if order is not a permutation
  DelassusMatrixD renumbered(std::span<const std::int32_t> order) const;

  /// \f$u \leftarrow u + W r\f$ (the rank-one terms included).
  /// @param[in] r Reactions, size D num_contacts()
  /// @param[in,out] u Velocities, size D num_contacts()
  void multiply_add(std::span<const double> r, std::span<double> u) const;

private:
  struct Contribution
  {
    std::int32_t row, col;
    Block block;
  };

  std::size_t _num_contacts;
  bool _finalized = false;
  /// The pending contributions bucketed by row, in the order they came:
  /// row a's are by_row[start[a]:start[a + 1]]
  void bucket_by_row(std::vector<std::int32_t>& start,
                     std::vector<std::int32_t>& by_row) const;
  std::vector<Contribution> _pending;

  // Compressed block rows
  std::vector<Block> _diagonal;
  std::vector<std::int32_t> _offsets;
  std::vector<std::int32_t> _columns;
  std::vector<Block> _blocks;

  // The rank-one terms, and the terms of each contact (compressed rows,
  // made by finalize(); empty without terms)
  std::vector<RankOne> _terms;
  std::vector<std::int32_t> _term_offsets;
  std::vector<TermEntry> _term_entries;
  void index_terms();
};

/// The 2D operator (2x2 blocks, (n, t)) and the 3D one (3x3, (n, t1, t2))
using DelassusMatrix = DelassusMatrixD<2>;
using DelassusMatrix3D = DelassusMatrixD<3>;
extern template class DelassusMatrixD<2>;
extern template class DelassusMatrixD<3>;

} // namespace softpack::contact
