#include "body_factors.h"

#include <Eigen/OrderingMethods>
#include <algorithm>
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
  for (std::size_t k = 0; k < body.input_position.size(); ++k)
    for (int c = 0; c < 2; ++c)
      P.indices()[2 * k + c] = 2 * body.input_position[k] + c;
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
                         const std::vector<bodies::BodyMatrix>& patterns)
    : _dim(bodies.dim()), _patterns(&patterns), _rows(bodies.num_bodies(), 0),
      _pattern_of(bodies.num_bodies(), -1), _perm(bodies.num_bodies()),
      _values(bodies.num_bodies()), _inverse_d(bodies.num_bodies())
{
  if (_dim != 2)
  {
    _general.resize(bodies.num_bodies());
    for (int b = 0; b < bodies.num_bodies(); ++b)
    {
      _rows[b] = bodies.body(b).num_dofs();
      if (!bodies.is_local(b))
        continue;
      _general[b] = make_general_factor("cholmod");
      _general[b]->analyze(patterns[b]);
    }
    return;
  }
  // Patterns met so far, by hash: (symbolic index, its canonical matrix)
  std::multimap<std::uint64_t, std::pair<int, bodies::BodyMatrix>> seen;
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    _rows[b] = bodies.body(b).num_dofs();
    if (!bodies.is_local(b))
      continue; // factorized where it is local
    const Permutation to_input = input_order(bodies.body(b));
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

namespace
{
/// The fill-reducing order of a pattern of nodes (2 DOFs each): AMD on the
/// nodes' graph, a node's DOFs kept together (x, then y), so that L is made
/// of 2x2 blocks.
Permutation node_ordering(const bodies::BodyMatrix& canonical)
{
  const int nodes = static_cast<int>(canonical.rows() / 2);
  std::vector<Eigen::Triplet<double>> links;
  for (int j = 0; j < canonical.outerSize(); ++j)
    for (bodies::BodyMatrix::InnerIterator it(canonical, j); it; ++it)
    {
      links.emplace_back(it.row() / 2, j / 2, 1.0);
      links.emplace_back(j / 2, it.row() / 2, 1.0);
    }
  bodies::BodyMatrix graph(nodes, nodes);
  graph.setFromTriplets(links.begin(), links.end());
  Permutation inverse; // AMD yields the inverse permutation
  Eigen::AMDOrdering<int> amd;
  amd(graph, inverse);
  const Permutation node_order = inverse.inverse();
  Permutation P(2 * nodes);
  for (int i = 0; i < nodes; ++i)
    for (int c = 0; c < 2; ++c)
      P.indices()[2 * i + c] = 2 * node_order.indices()[i] + c;
  return P;
}
} // namespace

void BodyFactors::analyze(Symbolic& s, const bodies::BodyMatrix& canonical)
{
  if (canonical.rows() % 2 != 0)
    throw std::invalid_argument("BodyFactors: a body's matrix has an odd "
                                "number of rows (2 DOFs per node expected)");
  s.ordering = node_ordering(canonical);
  // L's pattern, from a factorization of the (positive definite) values
  OrderedLDLT ldlt(permuted(canonical, s.ordering));
  if (ldlt.info() != Eigen::Success)
    throw std::runtime_error("BodyFactors: the matrix giving a body's "
                             "pattern is not positive definite");
  const auto& L = ldlt.matrixL().nestedExpression();
  const int nodes = static_cast<int>(L.rows() / 2);
  // Each node column's block rows: the nodes of the rows of its two
  // scalar columns below its diagonal block
  std::vector<std::vector<int>> rows(nodes);
  for (int j = 0; j < L.outerSize(); ++j)
    for (int k = L.outerIndexPtr()[j]; k < L.outerIndexPtr()[j + 1]; ++k)
      if (L.innerIndexPtr()[k] / 2 != j / 2)
        rows[j / 2].push_back(L.innerIndexPtr()[k] / 2);
  s.block_start.assign(1, 0);
  s.block_row.clear();
  for (std::vector<int>& r : rows)
  {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    s.block_row.insert(s.block_row.end(), r.begin(), r.end());
    s.block_start.push_back(static_cast<int>(s.block_row.size()));
  }
  const int diagonal_lower = 4 * static_cast<int>(s.block_row.size());
  s.destination.resize(L.nonZeros());
  for (int j = 0; j < L.outerSize(); ++j)
    for (int k = L.outerIndexPtr()[j]; k < L.outerIndexPtr()[j + 1]; ++k)
    {
      const int i = L.innerIndexPtr()[k], J = j / 2;
      if (i / 2 == J) // (y, x) of node J's diagonal block
      {
        s.destination[k] = diagonal_lower + J;
        continue;
      }
      const auto first = s.block_row.begin() + s.block_start[J];
      const auto last = s.block_row.begin() + s.block_start[J + 1];
      const int block = static_cast<int>(std::lower_bound(first, last, i / 2) -
                                         s.block_row.begin());
      s.destination[k] = 4 * block + i % 2 + 2 * (j % 2); // column-major
    }
}

bool BodyFactors::factorize_general(const Former& form)
{
  const int n = static_cast<int>(_general.size());
  bool ok = true;
#pragma omp parallel for schedule(dynamic) reduction(&& : ok) if (n >= 16)
  for (int b = 0; b < n; ++b)
  {
    if (!_general[b])
      continue;
    bodies::BodyMatrix values = (*_patterns)[b]; // the pattern
    form(b, values);
    ok = _general[b]->factorize(values) && ok;
  }
  return ok;
}

bool BodyFactors::factorize(const Former& form)
{
  if (_dim != 2)
    return factorize_general(form);
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
      const Symbolic& s = _symbolic[g];
      const bool good =
          ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0).all() &&
          L.nonZeros() == static_cast<Eigen::Index>(s.destination.size());
      ok = ok && good;
      if (!good)
        continue;
      _values[b].assign(4 * s.block_row.size() + s.num_nodes(), 0.0f);
      for (std::size_t k = 0; k < s.destination.size(); ++k)
        _values[b][s.destination[k]] = static_cast<float>(L.valuePtr()[k]);
      _inverse_d[b] = ldlt.vectorD().cwiseInverse();
    }
  }
  return ok;
}

Eigen::MatrixXd BodyFactors::solve(int b, const Eigen::MatrixXd& Y) const
{
  if (_dim == 2)
    throw std::logic_error("BodyFactors: 2D factors solve one column at a "
                           "time");
  return _general[b]->solve(Y);
}

Eigen::VectorXd BodyFactors::solve(int b, const Eigen::VectorXd& y) const
{
  if (_dim != 2)
    return _general[b]->solve(y);
  // L by 2x2 blocks: one index per four values, and a node's two unknowns
  // updated together (half the indexed loads of a scalar solve).
  const Symbolic& s = _symbolic[_pattern_of[b]];
  const int* start = s.block_start.data();
  const int* row = s.block_row.data();
  const float* L = _values[b].data();
  const float* lower = L + 4 * s.block_row.size(); // (y, x) of each node
  const int nodes = s.num_nodes();
  Eigen::VectorXd z = _perm[b] * y;
  double* x = z.data();
  for (int J = 0; J < nodes; ++J) // L z' = z, node column by node column
  {
    const double z0 = x[2 * J];
    const double z1 = x[2 * J + 1] - static_cast<double>(lower[J]) * z0;
    x[2 * J + 1] = z1;
    if (z0 == 0 && z1 == 0) // right-hand sides of compliance columns
      continue;             // are sparse
    for (int k = start[J]; k < start[J + 1]; ++k)
    {
      const float* B = L + 4 * k;
      double* xi = x + 2 * row[k];
      xi[0] -= static_cast<double>(B[0]) * z0 + static_cast<double>(B[2]) * z1;
      xi[1] -= static_cast<double>(B[1]) * z0 + static_cast<double>(B[3]) * z1;
    }
  }
  z.array() *= _inverse_d[b].array();
  for (int J = nodes - 1; J >= 0; --J) // L^T z' = z
  {
    double z0 = x[2 * J], z1 = x[2 * J + 1];
    for (int k = start[J]; k < start[J + 1]; ++k)
    {
      const float* B = L + 4 * k;
      const double* xi = x + 2 * row[k];
      z0 -=
          static_cast<double>(B[0]) * xi[0] + static_cast<double>(B[1]) * xi[1];
      z1 -=
          static_cast<double>(B[2]) * xi[0] + static_cast<double>(B[3]) * xi[1];
    }
    x[2 * J + 1] = z1;
    x[2 * J] = z0 - static_cast<double>(lower[J]) * z1;
  }
  return _perm[b].transpose() * z;
}

} // namespace softpack::dynamics
