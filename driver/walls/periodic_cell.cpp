#include "periodic_cell.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace softpack::dynamics
{

PeriodicCell PeriodicCell::moving(const std::array<double, 2>& a1,
                                  const std::array<double, 2>& a2,
                                  const std::array<double, 2>& gradient_x,
                                  const std::array<double, 2>& gradient_y)
{
  auto times = [&](const std::array<double, 2>& a) -> std::array<double, 2>
  {
    return {gradient_x[0] * a[0] + gradient_x[1] * a[1],
            gradient_y[0] * a[0] + gradient_y[1] * a[1]};
  };
  return {a1, a2, times(a1), times(a2)};
}

std::array<double, 2>
PeriodicCell::fractional(const std::array<double, 2>& x) const
{
  const double det = area();
  return {(a2[1] * x[0] - a2[0] * x[1]) / det,
          (-a1[1] * x[0] + a1[0] * x[1]) / det};
}

std::array<double, 2> PeriodicCell::widths() const
{
  const double det = std::abs(area());
  return {det / std::hypot(a2[0], a2[1]), det / std::hypot(a1[0], a1[1])};
}

double PeriodicCell::speed() const
{
  return std::max(std::hypot(a1_rate[0], a1_rate[1]),
                  std::hypot(a2_rate[0], a2_rate[1]));
}

void PeriodicCell::advance(double dt)
{
  for (int d = 0; d < 2; ++d)
  {
    a1[d] += dt * a1_rate[d];
    a2[d] += dt * a2_rate[d];
  }
}

int PeriodicCell::remap()
{
  if (!(std::abs(a2[0]) > remap_lean * std::abs(a1[0])))
    return 0;
  const int n = static_cast<int>(std::lround(a2[0] / a1[0]));
  for (int d = 0; d < 2; ++d)
  {
    a2[d] -= n * a1[d];
    a2_rate[d] -= n * a1_rate[d];
  }
  return n;
}

void check_body_fits(const PeriodicCell& cell, int body,
                     const std::array<double, 2>& extent)
{
  const std::array<double, 2> w = cell.widths();
  const double size = std::max(extent[0], extent[1]);
  const double half = 0.5 * std::min(w[0], w[1]);
  if (!(size < half))
    throw std::runtime_error(
        "periodic cell: body " + std::to_string(body) + " is " +
        std::to_string(size) +
        " m across, not smaller than half the cell (its widths " +
        std::to_string(w[0]) + " m and " + std::to_string(w[1]) +
        " m): it would touch two images of a neighbour; make the cell "
        "([cell] a1, a2) larger or compress it less");
}

} // namespace softpack::dynamics
