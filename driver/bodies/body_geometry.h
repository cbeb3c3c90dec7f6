#pragma once

#include "body_material.h"
#include "body_mesh.h"
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

struct ufcx_function_space;

/// The bodies' geometry as plain arrays, and the bodies built from it.
namespace softpack::bodies
{

/// A compiled space (forms::MaterialForms::function_space)
using SpaceFunction = ufcx_function_space* (*)(const char*);

/// The nodes of one P1 cell: a triangle's three (2D) or a tetrahedron's
/// four (3D), in the order dolfinx lists the cell's DOFs. Iterating gives
/// the cell's nodes only (a triangle keeps -1 as its fourth).
struct CellNodes
{
  std::array<std::int32_t, 4> n = {-1, -1, -1, -1};
  CellNodes() = default;
  CellNodes(std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d = -1)
      : n{a, b, c, d}
  {
  }
  /// 3 (triangle) or 4 (tetrahedron)
  int size() const { return n[3] < 0 ? 3 : 4; }
  std::int32_t operator[](int i) const { return n[i]; }
  std::int32_t& operator[](int i) { return n[i]; }
  const std::int32_t* begin() const { return n.data(); }
  const std::int32_t* end() const { return n.data() + size(); }
  std::int32_t* begin() { return n.data(); }
  std::int32_t* end() { return n.data() + size(); }
  bool operator==(const CellNodes&) const = default;
};

/// One deformable body: its nodes, cells and boundary, as indices into the
/// node vectors and cells of its BodySet.
struct Body
{
  /// Spatial dimension: 2 (triangles, plane strain) or 3 (tetrahedra); the
  /// node vectors hold dim interleaved components per node
  int dim = 2;
  /// Index of each local node in the BodySet's node vectors (its storage:
  /// the global node index, but in a distributed run's share that keeps
  /// its local bodies' entries only, BodySet::keep_storage)
  std::vector<std::int32_t> nodes;
  /// Global node (DOF block) index of each local node: the mesh's, the
  /// state file's and fields.h5's numbering
  std::vector<std::int32_t> global_nodes;
  /// Cells of the body (indices into BodyGeometry::cells, the mesh's cell
  /// order; increasing). This, cell_nodes and input_position are empty in a
  /// distributed run's share that keeps neither the body nor its mass
  /// (BodySet::set_local).
  std::vector<std::int32_t> cells;
  /// The same cells as their local nodes (three or four), in the order
  /// dolfinx lists a cell's DOFs: what the body assembly reads
  /// (body_assembly.h)
  std::vector<CellNodes> cell_nodes;
  /// Local indices of the nodes on the boundary (sorted)
  std::vector<std::int32_t> boundary_nodes;
  /// Boundary segments as pairs of local node indices, oriented
  /// counter-clockwise (the body lies on the left of a -> b), so that the
  /// outward normal is the tangent rotated clockwise (2D; empty in 3D)
  std::vector<std::array<std::int32_t, 2>> boundary_segments;
  /// For each local node: index in boundary_segments of the segment that
  /// starts at it and of the one that ends at it (-1 off the boundary; 2D)
  std::vector<std::int32_t> segment_from, segment_to;
  /// Boundary faces as triples of local node indices (3D; empty in 2D),
  /// oriented so that (b - a) x (c - a) points out of the body
  std::vector<std::array<std::int32_t, 3>> boundary_faces;
  /// Area (2D) or volume (3D) of the body in the reference configuration
  double reference_area = 0;
  /// For each local node, its position within the body in the input mesh
  /// file's node order. Bodies copied from one template mesh list their
  /// nodes alike in that file, so in this order their matrices have one
  /// sparsity pattern (which lets them share a symbolic factorization),
  /// whatever order dolfinx gave the nodes.
  std::vector<std::int32_t> input_position;

  /// Number of scalar DOFs of the body (dim per node)
  int num_dofs() const { return dim * static_cast<int>(nodes.size()); }
};

/// Every node and cell of the bodies in the numbering dolfinx gave the
/// displacement space of the mesh (its DOF order), with no dolfinx
/// object: a distributed run reads the mesh in one process and sends these
/// arrays to the others (parallel::broadcast_geometry), and a
/// BodySet is built from them.
struct BodyGeometry
{
  /// Spatial dimension: 2 (triangles) or 3 (tetrahedra)
  int dim = 2;
  /// Reference coordinates, interleaved x, y (, z) per node
  std::vector<double> x;
  /// The nodes of each cell, in the order dolfinx lists the cell's DOFs
  /// (Body::cell_nodes)
  std::vector<CellNodes> cells;
  /// Body id of each cell (0..num_bodies-1)
  std::vector<int> cell_body;
  /// Each node's index in the input mesh file (Body::input_position)
  std::vector<std::int64_t> node_input;
  /// Number of nodes
  std::int32_t num_nodes() const
  {
    return static_cast<std::int32_t>(x.size() / dim);
  }
  /// Number of bodies (the largest body id + 1)
  int num_bodies() const;
};

/// The displacement space of a set of materials in a dimension: the first
/// one's (every material's space is P1 vectors, so any one numbers the
/// nodes alike)
/// @throws std::invalid_argument if there is no material, or the first has
/// no forms in that dimension (forms::in_dimension)
SpaceFunction displacement_space(const std::vector<BodyMaterial>& materials,
                                 int dim = 2);

/// The geometry of a body mesh, numbered as the displacement space the
/// compiled forms declare (a material's `function_space`: every
/// material's is P1 vectors, so any one numbers the nodes alike)
/// @throws std::runtime_error if two cells of different bodies share a
/// node
BodyGeometry body_geometry(const BodyMesh& mesh, SpaceFunction function_space);

/// The mesh file's geometry (read_body_mesh, then body_geometry), read on
/// the calling process alone: the mesh lives during the call only
/// @throws std::runtime_error naming the file if its cells are not of the
/// forms' dimension (a 3D mesh given to the 2D driver)
BodyGeometry read_body_geometry(const std::filesystem::path& xdmf,
                                SpaceFunction function_space);

/// The bodies of a geometry: their nodes (global numbers), cells and
/// their nodes, boundaries (segments in 2D, faces in 3D), reference areas
/// (volumes in 3D) and input order
/// @throws std::runtime_error if two bodies share a node or a body has no
/// cell
std::vector<Body> build_bodies(const BodyGeometry& geometry);

/// Twice the signed area of triangle (a, b, c) of the interleaved
/// coordinates x
double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c);

/// Six times the signed volume of tetrahedron (a, b, c, d) of the
/// interleaved 3D coordinates x: (b - a) x (c - a) . (d - a)
double signed_volume6(std::span<const double> x, std::int32_t a, std::int32_t b,
                      std::int32_t c, std::int32_t d);

/// The reference measure of one cell of the interleaved coordinates x
/// (dim per node): a triangle's area or a tetrahedron's volume
double cell_measure(std::span<const double> x, const CellNodes& cell, int dim);

} // namespace softpack::bodies
