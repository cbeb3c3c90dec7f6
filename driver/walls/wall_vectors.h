#pragma once
// The dot product of two wall vectors (a point, a normal, a velocity, a
// force) of either dimension, one definition for the walls and the stages.
#include <array>
#include <cstddef>

namespace softpack::dynamics
{

/// a . b, summed in index order (the bits of a[0] b[0] + a[1] b[1] ...)
template <std::size_t N>
double dot(const std::array<double, N>& a, const std::array<double, N>& b)
{
  double sum = a[0] * b[0];
  for (std::size_t i = 1; i < N; ++i)
    sum += a[i] * b[i];
  return sum;
}

} // namespace softpack::dynamics
