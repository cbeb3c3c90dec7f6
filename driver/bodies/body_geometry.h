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

/// One deformable body: its nodes, cells and boundary, as indices into the
/// node vectors and cells of its BodySet.
struct Body
{
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
  /// The same cells as their three local nodes, in the order dolfinx lists
  /// a cell's DOFs: what the body assembly reads (body_assembly.h)
  std::vector<std::array<std::int32_t, 3>> cell_nodes;
  /// Local indices of the nodes on the boundary (sorted)
  std::vector<std::int32_t> boundary_nodes;
  /// Boundary segments as pairs of local node indices, oriented
  /// counter-clockwise (the body lies on the left of a -> b), so that the
  /// outward normal is the tangent rotated clockwise
  std::vector<std::array<std::int32_t, 2>> boundary_segments;
  /// For each local node: index in boundary_segments of the segment that
  /// starts at it and of the one that ends at it (-1 off the boundary)
  std::vector<std::int32_t> segment_from, segment_to;
  /// Area of the body in the reference configuration
  double reference_area = 0;
  /// For each local node, its position within the body in the input mesh
  /// file's node order. Bodies copied from one template mesh list their
  /// nodes alike in that file, so in this order their matrices have one
  /// sparsity pattern (which lets them share a symbolic factorization),
  /// whatever order dolfinx gave the nodes.
  std::vector<std::int32_t> input_position;

  /// Number of scalar DOFs of the body (2 per node)
  int num_dofs() const { return 2 * static_cast<int>(nodes.size()); }
};

/// Every node and cell of the bodies in the numbering dolfinx gave the
/// displacement space of the mesh (its DOF order), with no dolfinx
/// object: a distributed run reads the mesh in one process and sends these
/// arrays to the others (parallel::broadcast_geometry), and a
/// BodySet is built from them.
struct BodyGeometry
{
  /// Reference coordinates, interleaved x, y per node
  std::vector<double> x;
  /// The three nodes of each cell, in the order dolfinx lists the cell's
  /// DOFs (Body::cell_nodes)
  std::vector<std::array<std::int32_t, 3>> cells;
  /// Body id of each cell (0..num_bodies-1)
  std::vector<int> cell_body;
  /// Each node's index in the input mesh file (Body::input_position)
  std::vector<std::int64_t> node_input;
  /// Number of nodes
  std::int32_t num_nodes() const
  {
    return static_cast<std::int32_t>(x.size() / 2);
  }
  /// Number of bodies (the largest body id + 1)
  int num_bodies() const;
};

/// The displacement space of a set of materials: the first one's (every
/// material's space is P1 vectors, so any one numbers the nodes alike)
/// @throws std::invalid_argument if there is no material
SpaceFunction displacement_space(const std::vector<BodyMaterial>& materials);

/// The geometry of a body mesh, numbered as the displacement space the
/// compiled forms declare (a material's `function_space`: every
/// material's is P1 vectors, so any one numbers the nodes alike)
/// @throws std::runtime_error if two cells of different bodies share a
/// node
BodyGeometry body_geometry(const BodyMesh& mesh, SpaceFunction function_space);

/// The mesh file's geometry (read_body_mesh, then body_geometry), read on
/// the calling process alone: the mesh lives during the call only
BodyGeometry read_body_geometry(const std::filesystem::path& xdmf,
                                SpaceFunction function_space);

/// The bodies of a geometry: their nodes (global numbers), cells and
/// their nodes, boundaries, reference areas and input order
/// @throws std::runtime_error if two bodies share a node or a body has no
/// cell
std::vector<Body> build_bodies(const BodyGeometry& geometry);

/// Twice the signed area of triangle (a, b, c) of the interleaved
/// coordinates x
double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c);

} // namespace softpack::bodies
