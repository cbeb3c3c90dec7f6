#pragma once

#include <array>
#include <vector>

namespace softpack::bodies
{
class BodySet;

/// The nodal forces of a uniform acceleration g on the bodies (schema
/// [gravity]): \f$F = M (\mathbf{1} \otimes g)\f$, the consistent mass
/// applied to the uniform field, which is each node's lumped mass (the row
/// sums) times g, per unit length along z. A node vector of the bodies'
/// storage (interleaved, Body::nodes' numbering: global on one process,
/// BodySet::to_global makes it global on several); a body whose masses
/// this process does not keep (BodySet::kept_masses) gets zeros, which no
/// process integrates (each its local bodies).
std::vector<double> weight(const BodySet& bodies,
                           const std::array<double, 2>& g);

/// Body b's weight \f$\rho A g\f$ (N/m): the sum of weight()'s nodal
/// forces, from its density and reference area, known on every process.
std::array<double, 2> body_weight(const BodySet& bodies, int b,
                                  const std::array<double, 2>& g);

} // namespace softpack::bodies
