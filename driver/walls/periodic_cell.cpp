#include "periodic_cell.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace softpack::dynamics
{

std::array<double, 2> PeriodicCell::rate(const ImageShift& k) const
{
  const std::array<double, 2> s = shift(k);
  const auto& gx = velocity_gradient_x;
  const auto& gy = velocity_gradient_y;
  return {gx[0] * s[0] + gx[1] * s[1], gy[0] * s[0] + gy[1] * s[1]};
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
  const std::array<double, 2> r1 = rate({1, 0}), r2 = rate({0, 1});
  return std::max(std::hypot(r1[0], r1[1]), std::hypot(r2[0], r2[1]));
}

void PeriodicCell::advance(double dt)
{
  const std::array<double, 2> r1 = rate({1, 0}), r2 = rate({0, 1});
  for (int d = 0; d < 2; ++d)
  {
    a1[d] += dt * r1[d];
    a2[d] += dt * r2[d];
  }
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
