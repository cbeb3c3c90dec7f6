#pragma once

#include <dolfinx/mesh/Mesh.h>
#include <filesystem>
#include <memory>
#include <mpi.h>
#include <span>
#include <vector>

/// Meshes holding several disconnected deformable bodies.
namespace softpack::bodies
{

/// One dolfinx mesh holding all bodies, and the body of each cell.
struct BodyMesh
{
  /// All bodies in one (serial) mesh; bodies are disconnected components
  std::shared_ptr<dolfinx::mesh::Mesh> mesh;
  /// Body id (0..num_bodies-1) of each local cell, in dolfinx's cell order
  std::vector<int> cell_body;
  /// Number of bodies (max id + 1)
  int num_bodies = 0;
};

/// Read a mesh written by `softpack.mesh` (python): `NAME.xdmf` holding a
/// mesh of linear triangles (2D) or tetrahedra (3D) named "mesh" and cell
/// tags named "bodies".
/// @param[in] comm The communicator the mesh lives on (MPI_COMM_SELF: a
/// distributed run reads it in one process, read_body_geometry)
/// @param[in] xdmf Path of the XDMF file
/// @throws std::runtime_error naming the file if it is missing, is not a
/// mesh of linear triangles or tetrahedra, or has untagged cells
BodyMesh read_body_mesh(MPI_Comm comm, const std::filesystem::path& xdmf);

/// Build a body mesh from triangles (dim 2) or tetrahedra (dim 3) given in
/// memory (tests, generated geometries).
/// @param[in] comm The communicator the mesh lives on
/// @param[in] x Vertex coordinates, row-major (num_vertices, dim)
/// @param[in] cells Cell vertex indices, row-major (num_cells, dim + 1)
/// @param[in] cell_body Body id of each input cell
/// @param[in] dim 2 or 3
BodyMesh create_body_mesh(MPI_Comm comm, std::span<const double> x,
                          std::span<const std::int64_t> cells,
                          std::span<const int> cell_body, int dim = 2);

} // namespace softpack::bodies
