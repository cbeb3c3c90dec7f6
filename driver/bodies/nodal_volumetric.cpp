#include "nodal_volumetric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace softpack::bodies
{
namespace
{
/// One cell: its signed area and dA/dx over (x1, y1, x2, y2, x3, y3)
struct CellArea
{
  double area;
  std::array<double, 6> gradient;
};

CellArea cell_area(const Body& body, std::size_t c, std::span<const double> x,
                   std::span<const double> u)
{
  std::array<double, 6> p;
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 2; ++d)
    {
      const std::int32_t n = body.nodes[body.cell_nodes[c][i]];
      p[2 * i + d] = x[2 * n + d] + (u.empty() ? 0.0 : u[2 * n + d]);
    }
  CellArea a;
  a.area =
      0.5 * ((p[2] - p[0]) * (p[5] - p[1]) - (p[4] - p[0]) * (p[3] - p[1]));
  // node i's gradient from the edge opposite it (j, k in cyclic order)
  for (int i = 0; i < 3; ++i)
  {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    a.gradient[2 * i] = 0.5 * (p[2 * j + 1] - p[2 * k + 1]);
    a.gradient[2 * i + 1] = 0.5 * (p[2 * k] - p[2 * j]);
  }
  return a;
}

/// The current nodal volumes and each cell's current area and gradient
struct CurrentVolumes
{
  std::vector<double> v;
  std::vector<CellArea> cells;

  /// The sum over cell c's nodes of p_a = lambda ln J_a / J_a
  double cell_pressure(const Body& body, std::span<const double> v0,
                       std::size_t c, double lambda) const
  {
    double p = 0;
    for (const std::int32_t i : body.cell_nodes[c])
    {
      const double J = v[i] / v0[i];
      p += lambda * std::log(J) / J;
    }
    return p;
  }
};

CurrentVolumes current_volumes(const Body& body, std::span<const double> x,
                               std::span<const double> u)
{
  CurrentVolumes n{std::vector<double>(body.nodes.size(), 0.0), {}};
  n.cells.reserve(body.cell_nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    n.cells.push_back(cell_area(body, c, x, u));
    for (const std::int32_t i : body.cell_nodes[c])
      n.v[i] += n.cells.back().area / 3;
  }
  return n;
}

/// The cells at each node of the body (its patch)
std::vector<std::vector<std::int32_t>> cells_around(const Body& body)
{
  std::vector<std::vector<std::int32_t>> around(body.nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
    for (const std::int32_t i : body.cell_nodes[c])
      around[i].push_back(static_cast<std::int32_t>(c));
  return around;
}

/// d2A/dx_p dx_q of a triangle over its 6 coordinates
constexpr double area_hessian(int p, int q)
{
  const int i = p / 2, j = q / 2;
  if (p % 2 == q % 2 || i == j)
    return 0.0;
  // x_i y_j with j the next node of i: +1/2; the previous: -1/2
  const int sign = (j == (i + 1) % 3) ? 1 : -1;
  return (p % 2 == 0 ? 0.5 : -0.5) * sign;
}

/// Index in A's values of (row, col) (lower triangle, sorted columns)
std::int32_t value_index(const BodyMatrix& A, int row, int col)
{
  const int* first = A.innerIndexPtr() + A.outerIndexPtr()[col];
  const int* last = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(first, last, row);
  if (it == last || *it != row)
    throw std::logic_error("NodalPatches: the body matrix's pattern lacks "
                           "a patch entry (add_nodal_pattern)");
  return static_cast<std::int32_t>(it - A.innerIndexPtr());
}
} // namespace

void add_nodal_pattern(const Body& body,
                       std::vector<Eigen::Triplet<double>>& pattern)
{
  // Every pair of nodes of the cells around a node is coupled
  for (const std::vector<std::int32_t>& cells : cells_around(body))
    for (const std::int32_t ca : cells)
      for (const std::int32_t cb : cells)
        for (const std::int32_t ni : body.cell_nodes[ca])
          for (const std::int32_t nj : body.cell_nodes[cb])
            for (int di = 0; di < 2; ++di)
              for (int dj = 0; dj < 2; ++dj)
              {
                const int row = 2 * ni + di, col = 2 * nj + dj;
                if (stored_entry(row, col))
                  pattern.emplace_back(row, col, 0.0);
              }
}

NodalPatches::NodalPatches(const Body& body, std::span<const double> x)
    : _v0(body.nodes.size(), 0.0)
{
  // V0 summed in cell order, as the current volumes are
  _a0.reserve(body.cell_nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double a0 = _a0.emplace_back(cell_area(body, c, x, {}).area);
    for (const std::int32_t i : body.cell_nodes[c])
      _v0[i] += a0 / 3;
  }
  _around.assign(1, 0);
  _patch_start.assign(1, 0);
  for (const std::vector<std::int32_t>& cells : cells_around(body))
  {
    std::vector<std::int32_t> patch;
    for (const std::int32_t c : cells)
      patch.insert(patch.end(), body.cell_nodes[c].begin(),
                   body.cell_nodes[c].end());
    std::sort(patch.begin(), patch.end());
    patch.erase(std::unique(patch.begin(), patch.end()), patch.end());
    for (const std::int32_t c : cells)
    {
      std::array<std::int32_t, 3>& slot = _slot.emplace_back();
      for (int i = 0; i < 3; ++i)
        slot[i] = static_cast<std::int32_t>(
            std::lower_bound(patch.begin(), patch.end(),
                             body.cell_nodes[c][i]) -
            patch.begin());
    }
    _cell.insert(_cell.end(), cells.begin(), cells.end());
    _patch.insert(_patch.end(), patch.begin(), patch.end());
    _around.push_back(static_cast<std::int32_t>(_cell.size()));
    _patch_start.push_back(static_cast<std::int32_t>(_patch.size()));
  }
}

void NodalPatches::find_blocks(const BodyMatrix& K)
{
  _block_start.assign(1, 0);
  _block.clear();
  for (std::size_t a = 0; a + 1 < _patch_start.size(); ++a)
  {
    const std::int32_t* P = _patch.data() + _patch_start[a];
    const int m = _patch_start[a + 1] - _patch_start[a];
    for (int p = 0; p < m; ++p)
      for (int q = 0; q <= p; ++q)
      {
        const int r = P[p], s = P[q];
        _block.push_back({value_index(K, 2 * r, 2 * s),
                          r > s ? value_index(K, 2 * r, 2 * s + 1)
                                : value_index(K, 2 * r + 1, 2 * s + 1) - 1});
      }
    _block_start.push_back(static_cast<std::int64_t>(_block.size()));
  }
  _pattern_rows = K.rows();
  _pattern_entries = K.nonZeros();
}

void NodalPatches::add_cell_energy(const Body& body, std::span<const double> x,
                                   std::span<const double> u, double lambda,
                                   std::span<double> per_cell) const
{
  const CurrentVolumes n = current_volumes(body, x, u);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    for (const std::int32_t i : body.cell_nodes[c])
    {
      const double lnJ = std::log(n.v[i] / _v0[i]);
      // node i's energy V0 lambda/2 ln^2 J, this cell's share a0/3 of V0
      per_cell[body.cells[c]] += _a0[c] / 3 * 0.5 * lambda * lnJ * lnJ;
    }
  }
}

void NodalPatches::add_residual(const Body& body, std::span<const double> x,
                                std::span<const double> u, double lambda,
                                std::span<double> b) const
{
  const CurrentVolumes n = current_volumes(body, x, u);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    // each node's V_a holds A_e / 3
    const double p = n.cell_pressure(body, _v0, c, lambda);
    const std::array<double, 6>& g = n.cells[c].gradient;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        b[2 * body.nodes[body.cell_nodes[c][k]] + d] += p * g[2 * k + d] / 3;
  }
}

void NodalPatches::add_tangent(const Body& body, std::span<const double> x,
                               std::span<const double> u, double lambda,
                               BodyMatrix& K)
{
  if (K.rows() != _pattern_rows || K.nonZeros() != _pattern_entries)
    find_blocks(K);
  const CurrentVolumes n = current_volumes(body, x, u);
  double* values = K.valuePtr();
  std::vector<double> dv; // 3 dV_a over the patch's DOFs
  // sum_a lambda (1 - ln J_a) / (J_a^2 V0_a) dV_a (x) dV_a
  for (std::size_t a = 0; a + 1 < _patch_start.size(); ++a)
  {
    const double J = n.v[a] / _v0[a];
    const double w = lambda * (1 - std::log(J)) / (J * J * _v0[a]) / 9;
    const int m = _patch_start[a + 1] - _patch_start[a];
    dv.assign(2 * m, 0.0);
    for (std::int32_t k = _around[a]; k < _around[a + 1]; ++k)
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 2; ++d)
          dv[2 * _slot[k][i] + d] += n.cells[_cell[k]].gradient[2 * i + d];
    const std::array<std::int32_t, 2>* block = _block.data() + _block_start[a];
    for (int p = 0; p < m; ++p)
    {
      const double wx = w * dv[2 * p], wy = w * dv[2 * p + 1];
      for (int q = 0; q <= p; ++q, ++block)
      {
        const double sx = dv[2 * q], sy = dv[2 * q + 1];
        values[(*block)[0]] += wx * sx;
        values[(*block)[0] + 1] += wy * sx;
        if (q < p) // (x_p, y_q): above the diagonal when p = q
          values[(*block)[1]] += wx * sy;
        values[(*block)[1] + 1] += wy * sy;
      }
    }
  }
  // sum_a p_a d2V_a: per cell, the mean of its nodes' p times d2A
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double p = n.cell_pressure(body, _v0, c, lambda);
    for (int q = 0; q < 6; ++q)
      for (int r = 0; r < 6; ++r)
      {
        const int row = 2 * body.cell_nodes[c][q / 2] + q % 2,
                  col = 2 * body.cell_nodes[c][r / 2] + r % 2;
        if (stored_entry(row, col) && area_hessian(q, r) != 0)
          K.coeffRef(row, col) += p / 3 * area_hessian(q, r);
      }
  }
}

} // namespace softpack::bodies
