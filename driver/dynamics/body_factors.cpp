#include "body_factors.h"

#include <Eigen/OrderingMethods>
#include <cstdint>
#include <map>
#include <stdexcept>

namespace softpack::dynamics
{

namespace
{
using Permutation =
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;
/// Factorizes a matrix already in its fill-reducing order
using OrderedLDLT = Eigen::SimplicialLDLT<bodies::BodyMatrix, Eigen::Lower,
                                          Eigen::NaturalOrdering<int>>;

/// The lower triangle of P A P^T, with sorted row indices (so that equal
/// patterns have equal index arrays).
bodies::BodyMatrix permuted(const bodies::BodyMatrix& A, const Permutation& P)
{
  bodies::BodyMatrix unsorted(A.rows(), A.cols());
  unsorted.selfadjointView<Eigen::Lower>() =
      A.selfadjointView<Eigen::Lower>().twistedBy(P);
  // A storage-order round trip sorts each column's indices.
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows = unsorted;
  return bodies::BodyMatrix(rows);
}

/// Body b's DOFs (2 per node) in the input order of its nodes.
Permutation input_order(const bodies::Body& body)
{
  Permutation P(body.num_dofs());
  for (std::size_t k = 0; k < body.input_rank.size(); ++k)
    for (int c = 0; c < 2; ++c)
      P.indices()[2 * k + c] = 2 * body.input_rank[k] + c;
  return P;
}

/// A key that tells patterns apart: size, number of entries and a hash of
/// the index arrays (equal keys are then compared entry by entry).
std::uint64_t pattern_hash(const bodies::BodyMatrix& A)
{
  std::uint64_t h = 1469598103934665603ull; // FNV-1a
  auto mix = [&h](std::int64_t v)
  {
    h ^= static_cast<std::uint64_t>(v);
    h *= 1099511628211ull;
  };
  mix(A.rows());
  mix(A.nonZeros());
  for (Eigen::Index j = 0; j <= A.outerSize(); ++j)
    mix(A.outerIndexPtr()[j]);
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    mix(A.innerIndexPtr()[k]);
  return h;
}

bool same_pattern(const bodies::BodyMatrix& A, const bodies::BodyMatrix& B)
{
  return A.rows() == B.rows() && A.nonZeros() == B.nonZeros() &&
         std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1,
                    B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(),
                    B.innerIndexPtr());
}
} // namespace

BodyFactors::BodyFactors(const bodies::BodySet& bodies,
                         const std::vector<bodies::BodyMatrix>& patterns,
                         std::span<const char> owned)
    : _patterns(&patterns), _pattern_of(bodies.num_bodies(), -1),
      _perm(bodies.num_bodies()), _values(bodies.num_bodies()),
      _inverse_d(bodies.num_bodies())
{
  // Patterns met so far, by hash: (symbolic index, its canonical matrix)
  std::multimap<std::uint64_t, std::pair<int, bodies::BodyMatrix>> seen;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const Permutation to_input = input_order(bodies.body(b));
    _perm[b] = to_input;
    if (!owned.empty() && !owned[b])
      continue;
    bodies::BodyMatrix canonical = permuted(patterns[b], to_input);
    const std::uint64_t h = pattern_hash(canonical);
    int g = -1;
    for (auto [it, end] = seen.equal_range(h); it != end && g < 0; ++it)
      if (same_pattern(it->second.second, canonical))
        g = it->second.first;
    if (g < 0)
    {
      g = static_cast<int>(_symbolic.size());
      _symbolic.emplace_back();
      analyze(_symbolic.back(), canonical);
      seen.emplace(h, std::make_pair(g, std::move(canonical)));
    }
    _pattern_of[b] = g;
    _perm[b] = _symbolic[g].ordering * to_input;
  }
}

void BodyFactors::analyze(Symbolic& s, const bodies::BodyMatrix& canonical)
{
  // As Eigen::SimplicialLDLT orders: AMD on the whole symmetric pattern,
  // which yields the inverse permutation.
  Permutation inverse;
  Eigen::AMDOrdering<int> amd;
  bodies::BodyMatrix full = canonical.selfadjointView<Eigen::Lower>();
  amd(full, inverse);
  s.ordering = inverse.inverse();
  // L's pattern, from a factorization of the (positive definite) values
  OrderedLDLT ldlt(permuted(canonical, s.ordering));
  if (ldlt.info() != Eigen::Success)
    throw std::runtime_error("BodyFactors: the matrix giving a body's "
                             "pattern is not positive definite");
  const auto& L = ldlt.matrixL().nestedExpression();
  s.column_start.assign(L.outerIndexPtr(),
                        L.outerIndexPtr() + L.outerSize() + 1);
  s.row_index.assign(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros());
}

bool BodyFactors::factorize(const Former& form)
{
  // Bodies in pattern order, so that a thread re-analyzes (an elimination
  // tree, no ordering) only when it moves to another pattern.
  std::vector<int> order;
  for (int b = 0; b < static_cast<int>(_pattern_of.size()); ++b)
    if (_pattern_of[b] >= 0)
      order.push_back(b);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b)
                   { return _pattern_of[a] < _pattern_of[b]; });
  const int n = static_cast<int>(order.size());
  bool ok = true;
#pragma omp parallel reduction(&& : ok) if (n >= 16)
  {
    OrderedLDLT ldlt;
    int analyzed = -1;
#pragma omp for schedule(dynamic)
    for (int i = 0; i < n; ++i)
    {
      const int b = order[i], g = _pattern_of[b];
      bodies::BodyMatrix values = (*_patterns)[b]; // the pattern
      form(b, values);
      const bodies::BodyMatrix A = permuted(values, _perm[b]);
      if (analyzed != g)
        ldlt.analyzePattern(A);
      analyzed = g;
      ldlt.factorize(A);
      const auto& L = ldlt.matrixL().nestedExpression();
      const bool good =
          ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0).all() &&
          L.nonZeros() ==
              static_cast<Eigen::Index>(_symbolic[g].row_index.size());
      ok = ok && good;
      if (!good)
        continue;
      _values[b].assign(L.valuePtr(), L.valuePtr() + L.nonZeros());
      _inverse_d[b] = ldlt.vectorD().cwiseInverse();
    }
  }
  return ok;
}

Eigen::VectorXd BodyFactors::solve(int b, const Eigen::VectorXd& y) const
{
  const Symbolic& s = _symbolic[_pattern_of[b]];
  const int* start = s.column_start.data();
  const int* row = s.row_index.data();
  const float* L = _values[b].data();
  const Eigen::VectorXd& inverse_d = _inverse_d[b];
  Eigen::VectorXd z = _perm[b] * y;
  const int n = static_cast<int>(z.size());
  for (int j = 0; j < n; ++j) // L z' = z, column by column
  {
    const double zj = z[j];
    if (zj != 0) // right-hand sides of compliance columns are sparse
      for (int k = start[j]; k < start[j + 1]; ++k)
        z[row[k]] -= static_cast<double>(L[k]) * zj;
  }
  z.array() *= inverse_d.array();
  for (int j = n - 1; j >= 0; --j) // L^T z' = z
  {
    double zj = z[j];
    for (int k = start[j]; k < start[j + 1]; ++k)
      zj -= static_cast<double>(L[k]) * z[row[k]];
    z[j] = zj;
  }
  return _perm[b].transpose() * z;
}

} // namespace softpack::dynamics
