#pragma once

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <span>

namespace softpack::test
{

/// A continued run's displacement equals the uninterrupted run's, bit for
/// bit, and the bodies did move (a comparison of two rest states would
/// prove nothing).
inline void expect_same_displacement(std::span<const double> a,
                                     std::span<const double> b)
{
  ASSERT_EQ(a.size(), b.size());
  double scale = 0, diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    scale = std::max(scale, std::abs(a[i]));
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  ASSERT_GT(scale, 1e-4);
  EXPECT_EQ(diff, 0.0);
}

} // namespace softpack::test
