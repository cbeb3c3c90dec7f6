#pragma once

#include "BodySet.h"
#include "body_geometry.h"
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <vector>

/// The averaged nodal pressure (docs/incompressible.md; Bonet & Burton,
/// Commun. Numer. Meth. Engng 14:437, 1998, for tetrahedra): the volumetric
/// energy of a nearly incompressible body at its nodes instead of its cells,
///
///   U_vol = sum_a V0_a lambda/2 (ln J_a)^2,   J_a = V_a / V0_a,
///   V_a = sum_{cells at a} V_e(x) / (D + 1),
///
/// one constraint per node instead of per cell, so that P1 triangles and
/// tetrahedra do not lock as nu -> 1/2. A law that has it
/// (forms::MaterialForms::nodal_volumetric names its lambda) leaves that
/// part out of its UFL energy; NodalPatches adds it to one body's energy,
/// internal force and tangent. A triangle's area is bilinear in its nodes'
/// coordinates (dA/dx linear, d2A/dx2 constant), a tetrahedron's volume
/// trilinear (dV/dx quadratic, d2V/dx2 linear), so all is closed-form. Its
/// tangent couples each node's whole patch (add_nodal_pattern).
/// python/softpack/references/nodal_pressure.py is the same formulation in
/// numpy, the oracle of the tests.
namespace softpack::bodies
{

/// Add the entries the nodal tangent needs (every pair of DOFs of the
/// cells around each node, lower triangle) to a body's pattern
void add_nodal_pattern(const Body& body,
                       std::vector<Eigen::Triplet<double>>& pattern);

/// What the nodal energy of one body needs besides its displacement, made
/// once (BodyAssembly keeps one per body that has the law): the reference
/// nodal volumes V0_a and cell volumes, each node's cells and patch nodes,
/// and, from the first tangent on, where each pair of patch nodes' D x D
/// block lies in the body matrix's values. The tangent is then assembled
/// node by node as lambda (1 - ln J_a)/(J_a^2 V0_a) dV_a (x) dV_a, dV_a
/// gathered over the patch first: one product per pair of patch DOFs
/// written straight into the values, instead of one per pair of the
/// patch's cells' DOFs searched in the sparse matrix.
class NodalPatches
{
public:
  /// @param[in] x Reference coordinates (the BodySet's storage,
  /// interleaved); the body's cells and nodes as they are
  NodalPatches(const Body& body, std::span<const double> x);

  /// Whether these patches were made for this body's cells (a body keeps
  /// its local numbering: only a body whose cells arrived since, in a
  /// distributed run, does not fit)
  bool fits(const Body& body) const
  {
    return body.nodes.size() == _v0.size() &&
           body.cell_nodes.size() == _a0.size();
  }

  /// Each cell's share of the nodal energy into per_cell[body.cells[c]]
  /// (added): node a's energy split over its cells by their share of V0_a
  /// @param[in] x Reference coordinates, u displacement (the BodySet's
  /// storage, interleaved)
  void add_cell_energy(const Body& body, std::span<const double> x,
                       std::span<const double> u, double lambda,
                       std::span<double> per_cell) const;

  /// b += dU_vol/du (b the BodySet's storage vector)
  void add_residual(const Body& body, std::span<const double> x,
                    std::span<const double> u, double lambda,
                    std::span<double> b) const;

  /// K += d2U_vol/du2 (the body's matrix: local DOFs, lower triangle, its
  /// pattern from add_nodal_pattern)
  /// @throws std::logic_error if K's pattern lacks a patch entry
  void add_tangent(const Body& body, std::span<const double> x,
                   std::span<const double> u, double lambda, BodyMatrix& K);

private:
  void find_blocks(const BodyMatrix& K, int D);
  /// Each node's reference volume, each cell's (counted positive) and its
  /// orientation in the mesh (+-1)
  std::vector<double> _v0, _a0, _sign;
  /// Node a's cells: _cell[_around[a] .. _around[a + 1]); its patch nodes
  /// (sorted): _patch[_patch_start[a] .. _patch_start[a + 1])
  std::vector<std::int32_t> _around, _cell, _patch_start, _patch;
  /// For each entry of _cell: its D + 1 nodes' places in the node's patch
  std::vector<std::array<std::int32_t, 4>> _slot;
  /// Per node, per pair p >= q of its patch nodes (p (p + 1) / 2 + q from
  /// _block_start[a]), for each column D P_q + e (e < D): the value index
  /// of row D P_p (on the diagonal, p = q: e before that of (D P_p + e,
  /// D P_q + e), the upper entries not stored)
  std::vector<std::int64_t> _block_start;
  std::vector<std::array<std::int32_t, 3>> _block;
  /// The pattern _block was found in (rows, entries; -1: none yet)
  Eigen::Index _pattern_rows = -1, _pattern_entries = -1;
};

} // namespace softpack::bodies
