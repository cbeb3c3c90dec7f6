#pragma once

#include "BodySet.h"
#include "body_geometry.h"
#include <Eigen/SparseCore>
#include <span>
#include <vector>

/// The averaged nodal pressure (docs/incompressible.md; Bonet & Burton,
/// Commun. Numer. Meth. Engng 14:437, 1998): the volumetric energy of a
/// nearly incompressible body at its nodes instead of its triangles,
///
///   U_vol = sum_a V0_a lambda/2 (ln J_a)^2,   J_a = V_a / V0_a,
///   V_a = sum_{cells at a} A_e(x) / 3,
///
/// one constraint per node instead of per triangle, so that P1 triangles do
/// not lock as nu -> 1/2. A law that has it (forms::MaterialForms::
/// nodal_volumetric names its lambda) leaves that part out of its UFL
/// energy; these functions add it to one body's energy, internal force and
/// tangent. A triangle's area is bilinear in its nodes' coordinates: dA/dx
/// is linear and d2A/dx2 constant, so all is closed-form. Its tangent
/// couples each node's whole patch (nodal_pattern).
/// python/softpack/references/nodal_pressure.py is the same formulation in
/// numpy, the oracle of the tests.
namespace softpack::bodies
{

/// Add the entries the nodal tangent needs (every pair of DOFs of the
/// cells around each node, lower triangle) to a body's pattern
void add_nodal_pattern(const Body& body,
                       std::vector<Eigen::Triplet<double>>& pattern);

/// Each cell's share of the nodal energy into per_cell[body.cells[c]]
/// (added): node a's energy split over its cells by their share of V0_a
/// @param[in] x Reference coordinates, u displacement (the BodySet's
/// storage, interleaved)
void add_nodal_cell_energy(const Body& body, std::span<const double> x,
                           std::span<const double> u, double lambda,
                           std::span<double> per_cell);

/// b += dU_vol/du (b the BodySet's storage vector)
void add_nodal_residual(const Body& body, std::span<const double> x,
                        std::span<const double> u, double lambda,
                        std::span<double> b);

/// K += d2U_vol/du2 (the body's matrix: local DOFs, lower triangle, its
/// pattern from add_nodal_pattern)
void add_nodal_tangent(const Body& body, std::span<const double> x,
                       std::span<const double> u, double lambda, BodyMatrix& K);

} // namespace softpack::bodies
