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
/// (dim per node: x then y (then z)), of which only the lower triangle (row >=
/// col) is stored: the masses and tangents are symmetric (they derive from a
/// kinetic energy and a strain-energy density), the factorization reads the
/// lower triangle only, and the matrices are a third of the driver's memory.
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
/// The dimension is a property of the mesh (dim(): P1 triangles in plane
/// strain, or P1 tetrahedra), and the same code serves both: node vectors
/// hold dim interleaved components per node, each law runs its forms of
/// that dimension (forms::in_dimension: a plane-strain-only law is refused
/// in 3D).
///
/// State is kept in one displacement vector of node entries (dolfinx's DOF
/// ordering of the mesh, dim interleaved components per node; in a
/// distributed run's share its storage, keep_storage); every per-body
/// quantity is gathered from it through Body::nodes. Bodies never share a
/// node, so every operator is block-diagonal by body.
///
/// No dolfinx mesh is kept: the bodies' cells, nodes and boundaries come
/// from the geometry's arrays (read from a mesh by one process of a
/// distributed run, parallel::broadcast_geometry), and the forms, made on a
/// one-cell mesh, lend their kernels only: every computation runs the
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
  /// set_local assembles those kept (a distributed run's share, which
  /// would hold every body's for a moment otherwise)
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

  /// Spatial dimension: 2 (triangles, plane strain) or 3 (tetrahedra)
  int dim() const { return _dim; }

  /// Body b
  const Body& body(int b) const { return _bodies[b]; }

  /// The materials, and the material of body b
  const std::vector<BodyMaterial>& materials() const { return _materials; }
  int body_material(int b) const { return _body_material[b]; }
  /// Whether body b is rigid (its material's BodyMaterial::rigid)
  bool rigid(int b) const { return _materials[_body_material[b]].rigid; }

  /// Length of the node vectors (dim per stored node): the number of global
  /// scalar DOFs, or after keep_storage the share's number of them
  std::size_t num_dofs() const { return _reference_x.size(); }
  /// Number of global scalar DOFs (dim per node of the mesh)
  std::size_t num_global_dofs() const { return _dim * _num_global_nodes; }

  /// Keep the node vectors' entries of the flagged bodies' nodes, of every
  /// body's boundary nodes and of every rigid body's nodes only (what a
  /// distributed run's share reads, docs/mpi_design.md): a storage
  /// numbering with those nodes' global ones first (in global order: the
  /// same indices in every share), then the flagged bodies' interior nodes,
  /// then one node (NaN) for every other interior node. Body::nodes then
  /// index the storage. The displacement and reference coordinates are
  /// remapped (entries new to the storage are NaN: a rebalance fills
  /// them in, parallel::move_bodies); remap() does the same for other
  /// node vectors.
  /// May be called again with other flags.
  void keep_storage(std::span<const char> kept);
  /// A node vector of the storage before the last keep_storage in the
  /// storage after it (entries new to it NaN)
  void remap(std::vector<double>& v) const;
  /// The reference coordinates, writable: a rebalance fills in the
  /// arriving bodies' interiors (parallel::move_bodies)
  std::span<double> stored_reference_coordinates() { return _reference_x; }
  /// A global node vector (dim entries per mesh node) in this storage
  std::vector<double> from_global(std::span<const double> global) const;
  /// A node vector of this storage as a global one (the entries not
  /// stored: NaN)
  std::vector<double> to_global(std::span<const double> stored) const;
  /// The storage index that every unstored node maps to (-1 while every
  /// node is stored)
  std::int32_t unstored_node() const { return _unstored; }

  /// Displacement (interleaved x, y (, z) per stored node); writable
  std::span<double> displacement() { return _u; }
  std::span<const double> displacement() const { return _u; }

  /// Reference coordinates of the stored nodes (interleaved x, y (, z))
  std::span<const double> reference_coordinates() const { return _reference_x; }

  /// Current coordinates X + u of the nodes (interleaved, dim per node)
  std::vector<double> current_coordinates() const;

  /// Internal force \f$F_{int}(u) = \partial E/\partial u\f$ of the local
  /// bodies (local_bodies), written (not added) into the node vector f;
  /// the others' entries are zero
  void internal_force(std::span<double> f) const;

  /// Tangent stiffness \f$K(u)\f$ of each local body, assembled in place
  /// into matrices holding the body's sparsity pattern (create_matrices)
  void tangent(std::vector<BodyMatrix>& K) const;

  /// Zero matrices with each local body's sparsity pattern (lower
  /// triangle); the others get a matrix of their size with no entry
  std::vector<BodyMatrix> create_matrices() const;
  /// Zero matrices with the sparsity pattern of each body whose masses are
  /// kept (kept_masses), the others' empty
  std::vector<BodyMatrix> create_mass_matrices() const;

  /// Consistent mass matrix of each body whose mass is kept (kept_masses:
  /// every body until set_local, none if built without masses); the
  /// others' are empty. Computed once, and for a body that becomes local
  /// when it does.
  const std::vector<BodyMatrix>& consistent_mass() const { return _mass; }

  /// The bodies whose masses are kept: the local ones and every rigid body
  /// (dynamics::RigidBodies reads them all). The one place of the rule.
  std::vector<char> kept_masses() const { return kept_masses(_local_flag); }

  /// Lumped (vertex-quadrature, row-sum) mass of each body whose mass is
  /// kept (kept_masses, as consistent_mass), one per DOF; the others' are
  /// empty
  const std::vector<Eigen::VectorXd>& lumped_mass() const
  {
    return _lumped_mass;
  }

  /// Total strain energy \f$\int \Psi\,dx\f$ over the local bodies (the
  /// sum of body_strain_energy)
  double strain_energy() const;

  /// Strain energy of each cell (integral of Psi over the cell) of the
  /// local bodies, the others' zero
  std::vector<double> cell_strain_energy() const;

  /// Strain energy of each local body, the others' zero
  std::vector<double> body_strain_energy() const;

  /// Internal variables per cell (the most any of the materials' laws has;
  /// 0: no law has any, e.g. every hyperelastic one)
  int internal_stride() const { return _internal_stride; }
  /// The internal variables of every cell (internal_stride per cell,
  /// cells numbered as Body::cells; a cell of a law with fewer or none
  /// keeps its law's initial values, or zeros): what the forms of a
  /// viscoelastic law read beside the displacement
  std::span<const double> internal_variables() const { return _internal; }
  /// The same, to write: a rebalanced run moves a body's values to its new
  /// owner (parallel::move_bodies). On a distributed run's share the cells
  /// of the other ranks' bodies hold NaN (set_local): their owners alone
  /// relax them, and the state file gathers them from there.
  std::span<double> internal_variables() { return _internal; }
  /// Set them (a state restored)
  /// @throws std::invalid_argument if the size is not internal_variables'
  void set_internal_variables(std::span<const double> values);
  /// Relax the internal variables of the local bodies whose law has them
  /// over a step h at the current displacement (the law's
  /// internal_update), once per accepted step.
  /// @param[in,out] f Empty, or the internal force at the current
  /// displacement (internal_force): the relaxed bodies' entries are then
  /// replaced by their internal force at the relaxed values, in the same
  /// pass (the others' do not change)
  /// @return The drop of those bodies' strain energy it makes: the viscous
  /// dissipation (>= 0)
  double update_internal_variables(double h, std::span<double> f = {});

  /// Reference area (3D: volume) of each cell (NaN for a cell whose nodes
  /// are not stored, keep_storage). Before set_local only (every body's
  /// cells).
  std::vector<double> cell_reference_area() const;

  /// Current (deformed) area (3D: volume) of each body,
  /// \f$\int \det F\,dX\f$, from its boundary polygon (3D: its boundary
  /// faces)
  std::vector<double> body_current_area() const;

  /// Body id of each cell (cells numbered as Body::cells)
  const std::vector<int>& cell_body() const { return _cell_body; }

  /// Each cell's nodes (global node indices), cells numbered as
  /// Body::cells: the mesh, for outputs. Before set_local only (every
  /// body's cells).
  std::vector<CellNodes> cell_global_nodes() const;

  /// The bodies whose forces, tangents and energies this set computes, in
  /// increasing order (every body until set_local): the loops of the
  /// per-body work run over them
  std::span<const int> local_bodies() const { return _local; }
  /// Whether body b is local (local_bodies)
  bool is_local(int b) const { return _local_flag[b] != 0; }
  /// Whether stored node i (an index of the node vectors) is a local
  /// body's
  bool is_local_node(std::size_t i) const { return _local_node[i] != 0; }
  /// 1 for each stored node of a local body (is_local_node)
  std::span<const char> local_nodes() const { return _local_node; }

  /// Make `local` (increasing body indices) the local bodies: the per-body
  /// work (internal_force, tangent, energies) covers them only, the
  /// others' entries are left zero (a distributed run's share,
  /// parallel::Distribution). The masses (consistent and lumped) and the
  /// cell lists (Body::cells, cell_nodes, input_position) of the bodies
  /// kept_masses leaves out are freed; areas cover every body. May be
  /// called again (a rebalanced run): a body that becomes local must have
  /// been given its cell lists first (take_cell_lists). Call it after
  /// keep_storage (is_local_node indexes the storage).
  /// @throws std::invalid_argument if a body index is out of range or the
  /// list is not increasing
  /// @throws std::logic_error if a body kept now has no cell lists
  void set_local(std::vector<int> local);

  /// Body b's cells, their nodes and its input order as one list: what a
  /// rebalance sends with a body (parallel::move_bodies)
  std::vector<std::int32_t> cell_lists(int b) const;
  /// Give body b the cell lists written by cell_lists at the start of
  /// `in`; returns how many entries it read
  std::size_t take_cell_lists(int b, std::span<const std::int32_t> in);

private:
  /// The body assembly, from the per-body forms of each material in use
  /// (made on a one-cell mesh and dropped: their kernels and constants
  /// are what it keeps)
  void build_assembly();
  /// Every cell's internal variables at its law's initial values
  void init_internal();
  /// body_current_area in 3D: each body's volume from its boundary faces
  std::vector<double> body_current_volume() const;
  /// Every body's masses (all = false: empty ones, of each body's size)
  void build_mass(bool all);
  /// Zero matrices with the flagged bodies' patterns, the others' empty
  std::vector<BodyMatrix> create_matrices(std::span<const char> only) const;
  /// The masses kept with the given local flags (kept_masses)
  std::vector<char> kept_masses(std::span<const char> local) const;
  /// Mark the local bodies' stored nodes (is_local_node)
  void mark_local_nodes();
  /// Free the masses (consistent and lumped) of the bodies not flagged;
  /// assemble those flagged whose masses were freed before
  void keep_masses(std::span<const char> kept);
  /// Free the cell lists of the bodies not flagged
  void keep_cell_lists(std::span<const char> kept);
  /// Throw unless every body's cell lists are here (what the per-cell
  /// outputs of the whole mesh read)
  void require_every_cell(const char* what) const;

  int _dim = 2;
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
  /// The displacement (interleaved, dim per node)
  std::vector<double> _u;
  /// The internal variables (internal_stride per cell)
  std::vector<double> _internal;
  int _internal_stride = 0;
  std::vector<BodyMatrix> _mass;
  std::vector<Eigen::VectorXd> _lumped_mass;
  /// The per-body forms' kernels, run body by body
  std::unique_ptr<BodyAssembly> _assembly;
  /// The local bodies (increasing), 1 for each of them, and 1 for each
  /// of their stored nodes
  std::vector<int> _local;
  std::vector<char> _local_flag, _local_node;
};

/// The values (`stride` per cell, cell c's at stride * c) of the cells of
/// the flagged bodies (a flag per body; `cell_body`: each cell's body),
/// cell by cell in increasing order: what travels with a body to another
/// rank, or to rank 0 at an output
std::vector<double> pick_cells(std::span<const double> values, int stride,
                               std::span<const int> cell_body,
                               std::span<const char> flagged);
/// Write values picked by pick_cells with the same flags back in place
/// @return The number of values read from `in`
std::size_t place_cells(std::span<double> values, int stride,
                        std::span<const int> cell_body,
                        std::span<const char> flagged,
                        std::span<const double> in);

} // namespace softpack::bodies
