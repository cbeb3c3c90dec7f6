#pragma once

#include "body_geometry.h"
#include "body_materials.h"
#include "body_mesh.h"
#include <Eigen/SparseCore>
#include <array>
#include <map>
#include <material_registry.h>
#include <memory>
#include <span>
#include <string>
#include <vector>

/// Deformable bodies: finite-strain hyperelastic FEM, one DOF block per body.
namespace softpack::bodies
{
class BodyAssembly;

/// Sparse symmetric matrix of one body, in the body's local DOF numbering
/// (2 per node: x then y), of which only the lower triangle (row >= col) is
/// stored: the masses and tangents are symmetric (they derive from a kinetic
/// energy and a strain-energy density), the factorization reads the lower
/// triangle only, and the matrices are a third of the driver's memory.
/// Multiply with symmetric_product(), never with operator*.
using BodyMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// Whether a BodyMatrix stores entry (row, col): the one place of the rule
constexpr bool stored_entry(int row, int col)
{
  return row >= col;
}

/// A v for a BodyMatrix A (its lower triangle stored)
inline Eigen::VectorXd symmetric_product(const BodyMatrix& A,
                                         const Eigen::VectorXd& v)
{
  return A.selfadjointView<Eigen::Lower>() * v;
}

/// All deformable bodies of a simulation, built from the arrays of one
/// mesh (BodyGeometry), with per-body DOF blocks; each body is made of one
/// of the set's materials.
///
/// State is kept in one displacement vector of node entries (dolfinx's DOF
/// ordering of the mesh, two interleaved components per node; on a rank
/// of a distributed run its storage, keep_storage); every per-body
/// quantity is gathered from it through Body::nodes. Bodies never share a
/// node, so every operator is block-diagonal by body.
///
/// No dolfinx mesh is kept: the bodies' cells, nodes and boundaries come
/// from the geometry's arrays (read from a mesh by rank 0 of a distributed
/// run alone, parallel::broadcast_geometry), and the forms, made on a
/// one-triangle mesh, lend their kernels only: every computation runs the
/// kernels over Body::cell_nodes (BodyAssembly).
class BodySet
{
public:
  /// @param[in] mesh All bodies in one mesh
  /// @param[in] material Compiled material (see forms/material_registry.h)
  /// @param[in] parameters Value of every constant the material declares
  /// @param[in] density Mass density (kg per unit reference volume)
  /// @throws std::invalid_argument if a parameter is missing or unknown
  BodySet(BodyMesh mesh, const forms::MaterialForms& material,
          const std::map<std::string, double>& parameters, double density);
  /// Bodies of several materials: body b is made of
  /// materials[body_material[b]]: each body's cells run its material's
  /// kernels.
  /// @param[in] masses Assemble every body's masses now; false: none until
  /// set_owned assembles those a rank keeps (a distributed run's ranks,
  /// which would hold every body's for a moment otherwise)
  /// @throws std::invalid_argument naming the material (BodyMaterial::name)
  /// and key at fault, or a body_material of the wrong size or range
  BodySet(BodyGeometry geometry, std::vector<BodyMaterial> materials,
          std::vector<int> body_material, bool masses = true);
  /// The same from a mesh (numbered by the first material's space,
  /// body_geometry)
  BodySet(BodyMesh mesh, std::vector<BodyMaterial> materials,
          std::vector<int> body_material);
  BodySet(BodySet&&) noexcept;
  ~BodySet();

  /// Number of bodies
  int num_bodies() const { return static_cast<int>(_bodies.size()); }

  /// Body b
  const Body& body(int b) const { return _bodies[b]; }

  /// The materials, and the material of body b
  const std::vector<BodyMaterial>& materials() const { return _materials; }
  int body_material(int b) const { return _body_material[b]; }
  /// Whether body b is rigid (its material's BodyMaterial::rigid)
  bool rigid(int b) const { return _materials[_body_material[b]].rigid; }

  /// Length of the node vectors (2 per stored node): the number of global
  /// scalar DOFs, or after keep_storage this rank's share of them
  std::size_t num_dofs() const { return _reference_x.size(); }
  /// Number of global scalar DOFs (2 per node of the mesh)
  std::size_t num_global_dofs() const { return 2 * _num_global_nodes; }

  /// Keep the node vectors' entries of the flagged bodies' nodes, of every
  /// body's boundary nodes and of every rigid body's nodes only (what a
  /// rank of a distributed run reads, docs/mpi_design.md): a storage
  /// numbering with those nodes' global ones first (in global order: the
  /// same indices on every rank), then the flagged bodies' interior nodes,
  /// then one node (NaN) for every other interior node. Body::nodes then
  /// index the storage. The displacement and reference coordinates are
  /// remapped (entries new to the storage are NaN: a rebalance's new
  /// owner receives them); remap() does the same for other node vectors.
  /// May be called again with other flags.
  void keep_storage(std::span<const char> kept);
  /// A node vector of the storage before the last keep_storage in the
  /// storage after it (entries new to it NaN)
  void remap(std::vector<double>& v) const;
  /// The reference coordinates, writable: a rebalance's new owner fills in
  /// its arriving bodies' interiors (parallel::Ownership::move_to)
  std::span<double> stored_reference_coordinates() { return _reference_x; }
  /// A global node vector (2 entries per mesh node) in this storage
  std::vector<double> from_global(std::span<const double> global) const;
  /// A node vector of this storage as a global one (the entries not
  /// stored: NaN)
  std::vector<double> to_global(std::span<const double> stored) const;
  /// The storage index that every unstored node maps to (-1 while every
  /// node is stored)
  std::int32_t unstored_node() const { return _unstored; }

  /// Displacement (interleaved x, y per stored node); writable
  std::span<double> displacement() { return _u; }
  std::span<const double> displacement() const { return _u; }

  /// Reference coordinates of the stored nodes (interleaved x, y)
  std::span<const double> reference_coordinates() const { return _reference_x; }

  /// Current coordinates X + u of the nodes (interleaved x, y per node)
  std::vector<double> current_coordinates() const;

  /// Internal force \f$F_{int}(u) = \partial E/\partial u\f$ of all bodies,
  /// written (not added) into the node vector f
  void internal_force(std::span<double> f) const;

  /// internal_force of the owned bodies only (set_owned; all when unset):
  /// the others' entries are zero
  void owned_internal_force(std::span<double> f) const;

  /// Tangent stiffness \f$K(u)\f$ of each body, assembled in place into
  /// matrices holding the body's sparsity pattern (see create_matrices)
  void tangent(std::vector<BodyMatrix>& K) const;

  /// Zero matrices with each body's sparsity pattern (lower triangle)
  /// @param[in] only 1 for the bodies whose pattern is wanted (empty: all);
  /// the others get a matrix of their size with no entry (a distributed
  /// run's ranks keep the tangents of their own bodies only)
  std::vector<BodyMatrix>
  create_matrices(std::span<const char> only = {}) const;

  /// Consistent mass matrix of each body whose mass this rank keeps
  /// (kept_masses of set_owned's flags: every body until set_owned, none
  /// if built without masses); the others' are empty. Computed once, and
  /// for a body that comes to this rank when it does.
  const std::vector<BodyMatrix>& consistent_mass() const { return _mass; }

  /// The bodies whose masses a rank with the given owned flags keeps: its
  /// own, and every rigid body (dynamics::RigidBodies reads them all);
  /// every body when `owned` is empty. The one place of the rule.
  std::vector<char> kept_masses(std::span<const char> owned) const;

  /// Lumped (vertex-quadrature, row-sum) mass of each body whose mass this
  /// rank keeps (kept_masses, as consistent_mass), one per DOF; the others'
  /// are empty
  const std::vector<Eigen::VectorXd>& lumped_mass() const
  {
    return _lumped_mass;
  }

  /// Total strain energy \f$\int \Psi\,dx\f$ over all bodies (the sum of
  /// body_strain_energy)
  double strain_energy() const;

  /// Strain energy of each cell (integral of Psi over the cell)
  std::vector<double> cell_strain_energy() const;

  /// cell_strain_energy of the owned bodies' cells (set_owned; all when
  /// unset), the others' zero
  std::vector<double> owned_cell_strain_energy() const;

  /// Strain energy of each body
  std::vector<double> body_strain_energy() const;

  /// body_strain_energy of the owned bodies (set_owned; all when unset),
  /// the others' zero: what a rank of a distributed run computes of it
  std::vector<double> owned_body_strain_energy() const;

  /// Reference area of each cell (NaN for a cell whose nodes are not
  /// stored, keep_storage). Before set_owned only (every body's cells).
  std::vector<double> cell_reference_area() const;

  /// Current (deformed) area of each body, \f$\int \det F\,dX\f$,
  /// from its boundary polygon
  std::vector<double> body_current_area() const;

  /// Body id of each cell (cells numbered as Body::cells)
  const std::vector<int>& cell_body() const { return _cell_body; }

  /// Each cell's three nodes (global node indices), cells numbered as
  /// Body::cells: the mesh, for outputs. Before set_owned only (every
  /// body's cells).
  std::vector<std::array<std::int32_t, 3>> cell_global_nodes() const;

  /// Whether body b is one of the owned bodies (set_owned; every body
  /// when unset)
  bool owned(int b) const { return _owned.empty() || _owned[b]; }

  /// Restrict the per-body work of owned_internal_force and tangent to the
  /// bodies whose entry is nonzero (the bodies a rank of a distributed run
  /// owns, parallel::Ownership); the others' entries are left zero. The
  /// masses (consistent and lumped) and the cell lists (Body::cells,
  /// cell_nodes, input_rank) of the bodies kept_masses leaves out are
  /// freed; internal_force and body_strain_energy then cover the bodies
  /// whose cells are kept, areas every body. May be called again (a
  /// rebalanced run) with other flags: a body that comes to this rank must
  /// have been given its cell lists first (take_cell_lists).
  /// @throws std::invalid_argument if the size is not the number of bodies
  /// @throws std::logic_error if a body kept now has no cell lists
  void set_owned(std::vector<char> owned);

  /// Body b's cells, their nodes and its input order as one list: what a
  /// rebalance sends with a body to its new owner (Ownership::move_to)
  std::vector<std::int32_t> cell_lists(int b) const;
  /// Give body b the cell lists written by cell_lists at the start of
  /// `in`; returns how many entries it read
  std::size_t take_cell_lists(int b, std::span<const std::int32_t> in);

private:
  /// The body assembly, from the per-body forms of each material in use
  /// (made on a one-triangle mesh and dropped: their kernels and constants
  /// are what it keeps)
  void build_assembly();
  /// Every body's masses (all = false: empty ones, of each body's size)
  void build_mass(bool all);
  /// Strain energy of the flagged bodies' cells and of the flagged bodies
  /// (all when empty), the others' zero
  std::vector<double> strain_energy_by_cell(std::span<const char> only) const;
  std::vector<double> strain_energy_by_body(std::span<const char> only) const;
  /// Free the masses (consistent and lumped) of the bodies not flagged;
  /// assemble those flagged whose masses were freed before
  void keep_masses(std::span<const char> kept);
  /// Free the cell lists of the bodies not flagged
  void keep_cell_lists(std::span<const char> kept);
  /// Throw unless every body's cell lists are here (what the per-cell
  /// outputs of the whole mesh read)
  void require_every_cell(const char* what) const;

  std::vector<int> _cell_body;
  std::vector<BodyMaterial> _materials;
  std::vector<int> _body_material;
  std::vector<Body> _bodies;
  std::vector<double> _reference_x;
  std::size_t _num_global_nodes = 0;
  /// Global node of each stored node (empty: every node stored, in global
  /// order), the unstored nodes' index, and for each stored node its index
  /// before the last keep_storage (-1: new)
  std::vector<std::int32_t> _stored_global, _previous;
  std::int32_t _unstored = -1;
  /// The displacement (interleaved x, y per node)
  std::vector<double> _u;
  std::vector<BodyMatrix> _mass;
  std::vector<Eigen::VectorXd> _lumped_mass;
  /// The per-body forms' kernels, run body by body
  std::unique_ptr<BodyAssembly> _assembly;
  /// The bodies whose forces and tangents are computed (empty: all)
  std::vector<char> _owned;
};

} // namespace softpack::bodies
