#include "nodal_volumetric.h"

#include <array>
#include <cmath>

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

/// Per node: the reference and current nodal volumes; per cell: the
/// reference area, the current area and its gradient
struct NodalVolumes
{
  std::vector<double> v0, v, a0;
  std::vector<CellArea> cells;

  /// The sum over cell c's nodes of p_a = lambda ln J_a / J_a
  double cell_pressure(const Body& body, std::size_t c, double lambda) const
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

/// The cells at each node of the body (its patch)
std::vector<std::vector<std::int32_t>> cells_around(const Body& body)
{
  std::vector<std::vector<std::int32_t>> around(body.nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
    for (const std::int32_t i : body.cell_nodes[c])
      around[i].push_back(static_cast<std::int32_t>(c));
  return around;
}

NodalVolumes nodal_volumes(const Body& body, std::span<const double> x,
                           std::span<const double> u)
{
  NodalVolumes n{std::vector<double>(body.nodes.size(), 0.0),
                 std::vector<double>(body.nodes.size(), 0.0),
                 {},
                 {}};
  n.cells.reserve(body.cell_nodes.size());
  n.a0.reserve(body.cell_nodes.size());
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double a0 = n.a0.emplace_back(cell_area(body, c, x, {}).area);
    n.cells.push_back(cell_area(body, c, x, u));
    for (const std::int32_t i : body.cell_nodes[c])
    {
      n.v0[i] += a0 / 3;
      n.v[i] += n.cells.back().area / 3;
    }
  }
  return n;
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

void add_nodal_cell_energy(const Body& body, std::span<const double> x,
                           std::span<const double> u, double lambda,
                           std::span<double> per_cell)
{
  const NodalVolumes n = nodal_volumes(body, x, u);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    for (const std::int32_t i : body.cell_nodes[c])
    {
      const double lnJ = std::log(n.v[i] / n.v0[i]);
      // node i's energy V0 lambda/2 ln^2 J, this cell's share a0/3 of V0
      per_cell[body.cells[c]] += n.a0[c] / 3 * 0.5 * lambda * lnJ * lnJ;
    }
  }
}

void add_nodal_residual(const Body& body, std::span<const double> x,
                        std::span<const double> u, double lambda,
                        std::span<double> b)
{
  const NodalVolumes n = nodal_volumes(body, x, u);
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    // each node's V_a holds A_e / 3
    const double p = n.cell_pressure(body, c, lambda);
    const std::array<double, 6>& g = n.cells[c].gradient;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        b[2 * body.nodes[body.cell_nodes[c][k]] + d] += p * g[2 * k + d] / 3;
  }
}

void add_nodal_tangent(const Body& body, std::span<const double> x,
                       std::span<const double> u, double lambda, BodyMatrix& K)
{
  const NodalVolumes n = nodal_volumes(body, x, u);
  const std::vector<std::vector<std::int32_t>> around = cells_around(body);
  // sum_a lambda (1 - ln J_a) / (J_a^2 V0_a) dV_a (x) dV_a: the patch's
  // cells pairwise, dV_a = sum of their gradients / 3
  for (std::size_t a = 0; a < body.nodes.size(); ++a)
  {
    const double J = n.v[a] / n.v0[a];
    const double w = lambda * (1 - std::log(J)) / (J * J * n.v0[a]) / 9;
    for (const std::int32_t ca : around[a])
      for (const std::int32_t cb : around[a])
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            for (int di = 0; di < 2; ++di)
              for (int dj = 0; dj < 2; ++dj)
              {
                const int row = 2 * body.cell_nodes[ca][i] + di,
                          col = 2 * body.cell_nodes[cb][j] + dj;
                if (stored_entry(row, col))
                  K.coeffRef(row, col) += w * n.cells[ca].gradient[2 * i + di] *
                                          n.cells[cb].gradient[2 * j + dj];
              }
  }
  // sum_a p_a d2V_a: per cell, the mean of its nodes' p times d2A
  for (std::size_t c = 0; c < body.cell_nodes.size(); ++c)
  {
    const double p = n.cell_pressure(body, c, lambda);
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
