#pragma once

#include <array>
#include <vector>

namespace softpack::bodies
{
class BodySet;

/// A uniform acceleration (m/s^2) in space; the bodies of a 2D run take
/// its x and y (schema [gravity]: z = 0 when two components are given).
using Acceleration = std::array<double, 3>;

/// The nodal forces of a uniform acceleration g on the bodies (schema
/// [gravity]): \f$F = M (\mathbf{1} \otimes g)\f$, the consistent mass
/// applied to the uniform field, which is each node's lumped mass (the row
/// sums) times g (per unit length along z in 2D). A node vector of the
/// bodies' storage (interleaved, Body::nodes' numbering: global on one
/// process, BodySet::to_global makes it global on several); a body whose
/// masses this process does not keep (BodySet::kept_masses) gets zeros,
/// which no process integrates (each its local bodies).
std::vector<double> weight(const BodySet& bodies, const Acceleration& g);

/// Body b's weight \f$\rho |\Omega| g\f$ (N/m in 2D, N in 3D): the sum of
/// weight()'s nodal forces, from its density and reference area (2D) or
/// volume (3D), known on every process; z = 0 in 2D.
Acceleration body_weight(const BodySet& bodies, int b, const Acceleration& g);

} // namespace softpack::bodies
