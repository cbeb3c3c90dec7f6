#pragma once
// The serial order of contacts of either dimension (detection.h's and
// detection_3d.h's contact_order_key): one rule for both.
#include <algorithm>
#include <cstdint>

namespace softpack::dynamics
{

/// Pairs of bodies first (by the lower body, then the higher), then the
/// walls' contacts (by wall, then candidate body)
template <class C> std::int64_t contact_order_key_of(const C& c, int num_bodies)
{
  const std::int64_t n = num_bodies;
  if (c.wall >= 0)
    return n * n + c.wall * n + c.candidate_body;
  return std::min(c.candidate_body, c.antagonist_body) * n +
         std::max(c.candidate_body, c.antagonist_body);
}

} // namespace softpack::dynamics
