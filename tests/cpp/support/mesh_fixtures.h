#pragma once

#include <bodies/BodySet.h>
#include <bodies/body_mesh.h>
#include <dolfinx/fem/Function.h>
#include <filesystem>
#include <material_registry.h>
#include <memory>
#include <vector>

/// Small meshes built in memory for the body tests (no gmsh needed).
namespace softpack::test
{

/// Vertex coordinates and triangles of a disk triangulated ring by ring:
/// ring k (1..n) has 6k nodes on radius R k / n, so boundary nodes lie on
/// the circle exactly.
struct Triangulation
{
  std::vector<double> x;
  std::vector<std::int64_t> cells;
};

/// A disk of radius R centred at (cx, cy) with n rings.
Triangulation disk(double cx, double cy, double R, int n);

/// A rectangle [x0, x0 + w] x [y0, y0 + h] with nx x ny squares, each cut
/// into two triangles.
Triangulation rectangle(double x0, double y0, double w, double h, int nx,
                        int ny);

/// Several triangulations as one mesh, body i = i-th triangulation, on
/// `comm` (tests run on one rank).
bodies::BodyMesh bodies_mesh(const std::vector<Triangulation>& parts,
                             MPI_Comm comm = MPI_COMM_WORLD);

/// Write a body mesh as `softpack.scene.mesh` does: `xdmf` (+ .h5) holding
/// the mesh "mesh" and the cell tags "bodies" (what read_body_mesh reads).
void write_body_mesh(const bodies::BodyMesh& mesh,
                     const std::filesystem::path& xdmf);

/// The displacement of `bodies` as a dolfinx Function on `law`'s space over
/// `mesh`, the mesh the BodySet was built from (a BodySet keeps no mesh:
/// tests that compare with dolfinx's assemblers keep their own). The space
/// is made as the BodySet makes it, so its DOFs number the nodes alike.
std::shared_ptr<dolfinx::fem::Function<double>>
dolfinx_displacement(const std::shared_ptr<dolfinx::mesh::Mesh>& mesh,
                     const forms::MaterialForms& law,
                     const bodies::BodySet& bodies);

} // namespace softpack::test
