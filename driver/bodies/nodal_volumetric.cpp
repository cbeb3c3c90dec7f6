#include "nodal_volumetric.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace softpack::bodies
{
namespace
{
/// One cell: its signed measure (a triangle's area, a tetrahedron's volume)
/// times its orientation, and the gradient of that over its nodes'
/// coordinates (D per node, D (D + 1) used)
struct CellVolume
{
  double volume;
  std::array<double, 12> gradient;
};

/// The coordinates x + u of cell c's nodes, D per node
std::array<double, 12> cell_points(const Body& body, std::size_t c,
                                   std::span<const double> x,
                                   std::span<const double> u)
{
  const int D = body.dim;
  std::array<double, 12> p{};
  for (int i = 0; i < D + 1; ++i)
    for (int d = 0; d < D; ++d)
    {
      const std::int32_t n = body.nodes[body.cell_nodes[c][i]];
      p[D * i + d] = x[D * n + d] + (u.empty() ? 0.0 : u[D * n + d]);
    }
  return p;
}

/// The face opposite each node of a tetrahedron, ordered so that
/// dV/dx_i = (x_b - x_a) x (x_c - x_a) / 6 for V = (x1 - x0).((x2 - x0) x
/// (x3 - x0)) / 6
constexpr int opposite_face[4][3] = {
    {1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

/// x_j - x_i of a tetrahedron's points
Eigen::Vector3d edge(const std::array<double, 12>& p, int i, int j)
{
  return {p[3 * j] - p[3 * i], p[3 * j + 1] - p[3 * i + 1],
          p[3 * j + 2] - p[3 * i + 2]};
}

/// A cell's measure and gradient; `sign` its reference orientation (+-1:
/// every measure is counted positive in the reference state)
CellVolume cell_volume(const Body& body, std::size_t c,
                       std::span<const double> x, std::span<const double> u,
                       double sign = 1.0)
{
  const std::array<double, 12> p = cell_points(body, c, x, u);
  CellVolume a;
  a.gradient.fill(0.0);
  if (body.dim == 2)
  {
    a.volume =
        0.5 * ((p[2] - p[0]) * (p[5] - p[1]) - (p[4] - p[0]) * (p[3] - p[1]));
    // node i's gradient from the edge opposite it (j, k in cyclic order)
    for (int i = 0; i < 3; ++i)
    {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      a.gradient[2 * i] = 0.5 * (p[2 * j + 1] - p[2 * k + 1]);
      a.gradient[2 * i + 1] = 0.5 * (p[2 * k] - p[2 * j]);
    }
  }
  else
  {
    a.volume = edge(p, 0, 1).dot(edge(p, 0, 2).cross(edge(p, 0, 3))) / 6;
    for (int i = 0; i < 4; ++i)
    {
      const int* f = opposite_face[i];
      const Eigen::Vector3d g =
          edge(p, f[0], f[1]).cross(edge(p, f[0], f[2])) / 6;
      for (int d = 0; d < 3; ++d)
        a.gradient[3 * i + d] = g[d];
    }
  }
  if (sign != 1.0)
  {
    a.volume *= sign;
    for (double& g : a.gradient)
      g *= sign;
  }
  return a;
}

/// The current nodal volumes and each cell's current measure and gradient
struct CurrentVolumes
{
  std::vector<double> v;
  std::vector<CellVolume> cells;

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
                               std::span<const double> u,
                               std::span<const double> sign)
{
  CurrentVolumes n{std::vector<double>(body.nodes.size(), 0.0), {}};
  n.cells.reserve(body.cell_nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    n.cells.push_back(cell_volume(body, c, x, u, sign[c]));
    for (const std::int32_t i : body.cell_nodes[c])
      n.v[i] += n.cells.back().volume / (body.dim + 1);
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

/// d2V/dx dx of a tetrahedron over its 12 coordinates (row-major): node
/// i's gradient (x_b - x_a) x (x_c - x_a) / 6 differentiated, [v] the
/// cross-product matrix (v x .): d/dx_b = -[x_c - x_a] / 6, d/dx_c =
/// [x_b - x_a] / 6, d/dx_a = [x_c - x_b] / 6, d/dx_i = 0. Linear in x.
std::array<double, 144> volume_hessian(const std::array<double, 12>& p,
                                       double sign)
{
  std::array<double, 144> H{};
  auto add_cross = [&](int i, int j, const Eigen::Vector3d& v, double s)
  {
    // [v] = ((0, -v3, v2), (v3, 0, -v1), (-v2, v1, 0))
    const double m[3][3] = {
        {0, -v[2], v[1]}, {v[2], 0, -v[0]}, {-v[1], v[0], 0}};
    for (int d = 0; d < 3; ++d)
      for (int e = 0; e < 3; ++e)
        H[12 * (3 * i + d) + 3 * j + e] += sign * s * m[d][e] / 6;
  };
  for (int i = 0; i < 4; ++i)
  {
    const int* f = opposite_face[i];
    add_cross(i, f[1], edge(p, f[0], f[2]), -1.0);
    add_cross(i, f[2], edge(p, f[0], f[1]), 1.0);
    add_cross(i, f[0], edge(p, f[1], f[2]), 1.0);
  }
  return H;
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
/// K += sum_a p_a d2V_a: per cell, the mean of its nodes' p times d2V_e
void add_volume_hessian(const Body& body, std::span<const double> x,
                        std::span<const double> u, const CurrentVolumes& n,
                        std::span<const double> v0,
                        std::span<const double> sign, double lambda,
                        BodyMatrix& K)
{
  const int D = body.dim, m = D * (D + 1);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double p = n.cell_pressure(body, v0, c, lambda);
    std::array<double, 144> H{};
    if (D == 3)
      H = volume_hessian(cell_points(body, c, x, u), sign[c]);
    for (int q = 0; q < m; ++q)
      for (int r = 0; r < m; ++r)
      {
        const double h = D == 2 ? sign[c] * area_hessian(q, r) : H[m * q + r];
        const int row = D * body.cell_nodes[c][q / D] + q % D,
                  col = D * body.cell_nodes[c][r / D] + r % D;
        if (stored_entry(row, col) && h != 0)
          K.coeffRef(row, col) += p / (D + 1) * h;
      }
  }
}

} // namespace

void add_nodal_pattern(const Body& body,
                       std::vector<Eigen::Triplet<double>>& pattern)
{
  // Every pair of nodes of the cells around a node is coupled: each pair
  // once (listed per cell pair, a tetrahedral mesh's pairs would repeat
  // a hundred times over)
  const int D = body.dim;
  std::vector<std::vector<std::int32_t>> below(body.nodes.size());
  for (const std::vector<std::int32_t>& cells : cells_around(body))
    for (const std::int32_t ca : cells)
      for (const std::int32_t cb : cells)
        for (const std::int32_t ni : body.cell_nodes[ca])
          for (const std::int32_t nj : body.cell_nodes[cb])
            if (nj <= ni)
              below[ni].push_back(nj);
  for (std::size_t ni = 0; ni < below.size(); ++ni)
  {
    std::vector<std::int32_t>& row = below[ni];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (const std::int32_t nj : row)
      for (int di = 0; di < D; ++di)
        for (int dj = 0; dj < D; ++dj)
        {
          const int r = D * static_cast<int>(ni) + di, c = D * nj + dj;
          if (stored_entry(r, c))
            pattern.emplace_back(r, c, 0.0);
        }
    std::vector<std::int32_t>().swap(row);
  }
}

NodalPatches::NodalPatches(const Body& body, std::span<const double> x)
    : _v0(body.nodes.size(), 0.0)
{
  // V0 summed in cell order, as the current volumes are; a mesh's cells
  // may all be ordered clockwise (negative measures): each counts positive
  _a0.reserve(body.cell_nodes.size());
  _sign.reserve(body.cell_nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double signed_volume = cell_volume(body, c, x, {}).volume;
    _sign.push_back(signed_volume < 0 ? -1.0 : 1.0);
    const double a0 = _a0.emplace_back(_sign.back() * signed_volume);
    for (const std::int32_t i : body.cell_nodes[c])
      _v0[i] += a0 / (body.dim + 1);
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
      std::array<std::int32_t, 4>& slot = _slot.emplace_back();
      for (int i = 0; i < body.cell_nodes[c].size(); ++i)
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

void NodalPatches::find_blocks(const BodyMatrix& K, int D)
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
        // column D s + e from row D r on (from its diagonal when r = s,
        // the entry e rows earlier standing for the upper ones)
        const int r = P[p], s = P[q];
        std::array<std::int32_t, 3>& block = _block.emplace_back();
        for (int e = 0; e < D; ++e)
          block[e] = r > s ? value_index(K, D * r, D * s + e)
                           : value_index(K, D * r + e, D * s + e) - e;
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
  const CurrentVolumes n = current_volumes(body, x, u, _sign);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    for (const std::int32_t i : body.cell_nodes[c])
    {
      const double lnJ = std::log(n.v[i] / _v0[i]);
      // node i's energy V0 lambda/2 ln^2 J, this cell's share V0_e/(D+1)
      per_cell[body.cells[c]] +=
          _a0[c] / (body.dim + 1) * 0.5 * lambda * lnJ * lnJ;
    }
  }
}

void NodalPatches::add_residual(const Body& body, std::span<const double> x,
                                std::span<const double> u, double lambda,
                                std::span<double> b) const
{
  const int D = body.dim;
  const CurrentVolumes n = current_volumes(body, x, u, _sign);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    // each node's V_a holds V_e / (D + 1)
    const double p = n.cell_pressure(body, _v0, c, lambda);
    const std::array<double, 12>& g = n.cells[c].gradient;
    for (int k = 0; k < D + 1; ++k)
      for (int d = 0; d < D; ++d)
        b[D * body.nodes[body.cell_nodes[c][k]] + d] +=
            p * g[D * k + d] / (D + 1);
  }
}

void NodalPatches::add_tangent(const Body& body, std::span<const double> x,
                               std::span<const double> u, double lambda,
                               BodyMatrix& K)
{
  const int D = body.dim;
  if (K.rows() != _pattern_rows || K.nonZeros() != _pattern_entries)
    find_blocks(K, D);
  const CurrentVolumes n = current_volumes(body, x, u, _sign);
  double* values = K.valuePtr();
  std::vector<double> dv; // (D + 1) dV_a over the patch's DOFs
  // sum_a lambda (1 - ln J_a) / (J_a^2 V0_a) dV_a (x) dV_a
  for (std::size_t a = 0; a + 1 < _patch_start.size(); ++a)
  {
    const double J = n.v[a] / _v0[a];
    const double w =
        lambda * (1 - std::log(J)) / (J * J * _v0[a]) / ((D + 1) * (D + 1));
    const int m = _patch_start[a + 1] - _patch_start[a];
    dv.assign(D * m, 0.0);
    for (std::int32_t k = _around[a]; k < _around[a + 1]; ++k)
      for (int i = 0; i < D + 1; ++i)
        for (int d = 0; d < D; ++d)
          dv[D * _slot[k][i] + d] += n.cells[_cell[k]].gradient[D * i + d];
    const std::array<std::int32_t, 3>* block = _block.data() + _block_start[a];
    for (int p = 0; p < m; ++p)
    {
      double wd[3];
      for (int d = 0; d < D; ++d)
        wd[d] = w * dv[D * p + d];
      for (int q = 0; q <= p; ++q, ++block)
        for (int e = 0; e < D; ++e)
        {
          const double s = dv[D * q + e];
          // (d < e, p = q): above the diagonal, not stored
          for (int d = (q < p ? 0 : e); d < D; ++d)
            values[(*block)[e] + d] += wd[d] * s;
        }
    }
  }
  add_volume_hessian(body, x, u, n, _v0, _sign, lambda, K);
}

} // namespace softpack::bodies
