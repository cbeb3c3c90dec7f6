#pragma once

// What the periodic-cell tests share: their disks, the six-disk assembly
// and the 3 x 3 lattice (test_periodic_cell.cpp, test_servo_cell.cpp,
// test_cell_stress_control.cpp).
#include <array>
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <bodies/stress_average.h>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <vector>
#include <walls/periodic_cell.h>

namespace softpack::test::cell
{
constexpr double mu = 0.15e6, rho = 1180, R = 0.01;

/// Neo-Hookean disks of radius R (24 boundary nodes) at the centres
inline bodies::BodySet disks(const std::vector<std::array<double, 2>>& centres)
{
  std::vector<test::Triangulation> parts;
  for (const auto& c : centres)
    parts.push_back(test::disk(c[0], c[1], R, 4));
  return bodies::BodySet(test::bodies_mesh(parts),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
}

/// The six-disk assembly of a 0.07 m cell, moved by `offset`
inline std::vector<std::array<double, 2>>
six(const std::array<double, 2>& offset)
{
  const std::vector<std::array<double, 2>> base = {
      {0.012, 0.011}, {0.035, 0.016}, {0.058, 0.013},
      {0.021, 0.043}, {0.047, 0.041}, {0.060, 0.061}};
  std::vector<std::array<double, 2>> out;
  for (const auto& b : base)
    out.push_back({b[0] + offset[0], b[1] + offset[1]});
  return out;
}

/// The side of a square cell holding a 3 x 3 lattice of the disks with
/// `gap` between neighbours (and between a disk and its images)
inline double lattice_side(double gap)
{
  return 3 * (2 * R + gap);
}

/// The centres of that lattice, (i + 1/2, j + 1/2) of the cell's thirds
inline std::vector<std::array<double, 2>> lattice(double gap)
{
  const double c = lattice_side(gap);
  std::vector<std::array<double, 2>> centres;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      centres.push_back({(i + 0.5) * c / 3, (j + 0.5) * c / 3});
  return centres;
}

/// The bodies' own mean stress over the cell, (1/det h) sum_b int sigma da:
/// xx, yy, xy, yx, tension positive
inline std::array<double, 4> fe_stress(const bodies::BodySet& bodies,
                                       const dynamics::PeriodicCell& cell)
{
  std::array<double, 4> s = {0, 0, 0, 0};
  for (const bodies::CauchyIntegral& c : bodies::cauchy_integrals(bodies))
    for (int i = 0; i < 4; ++i)
      s[i] += c[i] / cell.area();
  return s;
}

} // namespace softpack::test::cell
