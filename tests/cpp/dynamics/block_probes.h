#pragma once

// Probes of a single body's motion shared by the contact-law dynamics tests
// (cohesive, bonded): its mean velocity and its lowest point.

#include <bodies/BodySet.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace softpack::test
{

/// Body 0's mean velocity along d: its momentum (lumped masses times the
/// velocities v) over `mass`
inline double mean_velocity(const bodies::BodySet& set,
                            std::span<const double> v, int d, double mass)
{
  const Eigen::VectorXd& m = set.lumped_mass()[0];
  double p = 0;
  for (std::size_t k = 0; k < set.body(0).nodes.size(); ++k)
    p += m[2 * k + d] * v[2 * set.body(0).nodes[k] + d];
  return p / mass;
}

/// The lowest y of the bodies' current nodes
inline double lowest_point(const bodies::BodySet& set)
{
  const std::vector<double> x = set.current_coordinates();
  double y = INFINITY;
  for (std::size_t i = 1; i < x.size(); i += 2)
    y = std::min(y, x[i]);
  return y;
}

} // namespace softpack::test
