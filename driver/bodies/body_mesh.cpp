#include "body_mesh.h"

#include <algorithm>
#include <dolfinx/fem/CoordinateElement.h>
#include <dolfinx/graph/AdjacencyList.h>
#include <dolfinx/io/XDMFFile.h>
#include <dolfinx/mesh/MeshTags.h>
#include <dolfinx/mesh/utils.h>
#include <stdexcept>

namespace softpack::bodies
{
using namespace dolfinx;
namespace
{
int count_bodies(const std::vector<int>& cell_body)
{
  return cell_body.empty()
             ? 0
             : *std::max_element(cell_body.begin(), cell_body.end()) + 1;
}
} // namespace

BodyMesh read_body_mesh(MPI_Comm comm, const std::filesystem::path& xdmf)
{
  if (!std::filesystem::exists(xdmf))
    throw std::runtime_error("mesh file " + xdmf.string() + " does not exist");
  if (std::filesystem::path h5 = xdmf;
      !std::filesystem::exists(h5.replace_extension(".h5")))
    throw std::runtime_error("mesh file " + xdmf.string() + ": its data file " +
                             h5.string() + " does not exist");

  dolfinx::io::XDMFFile file(comm, xdmf, "r");
  const auto [type, degree] = file.read_cell_type("mesh");
  if ((type != mesh::CellType::triangle &&
       type != mesh::CellType::tetrahedron) ||
      degree != 1)
    throw std::runtime_error("mesh file " + xdmf.string() +
                             ": expected linear triangles (2D) or "
                             "tetrahedra (3D)");
  fem::CoordinateElement cmap(type, 1);
  auto mesh = std::make_shared<dolfinx::mesh::Mesh>(
      file.read_mesh(cmap, mesh::GhostMode::none, "mesh"));
  const int dim = type == mesh::CellType::triangle ? 2 : 3;
  if (mesh->geometry().dim() != dim)
    throw std::runtime_error("mesh file " + xdmf.string() + ": " +
                             (dim == 2 ? "triangles" : "tetrahedra") +
                             " with coordinates of dimension " +
                             std::to_string(mesh->geometry().dim()));
  dolfinx::mesh::MeshTags<std::int32_t> tags =
      file.read_meshtags(mesh, "bodies");

  const int tdim = mesh->topology().dim();
  const std::int32_t num_cells = mesh->topology().index_map(tdim)->size_local();
  std::vector<int> cell_body(num_cells, -1);
  for (std::size_t i = 0; i < tags.indices().size(); ++i)
    cell_body[tags.indices()[i]] = tags.values()[i];
  if (std::find(cell_body.begin(), cell_body.end(), -1) != cell_body.end())
    throw std::runtime_error("mesh file " + xdmf.string() +
                             ": some cells carry no 'bodies' tag");
  const int n = count_bodies(cell_body);
  return {mesh, std::move(cell_body), n};
}

BodyMesh create_body_mesh(MPI_Comm comm, std::span<const double> x,
                          std::span<const std::int64_t> cells,
                          std::span<const int> cell_body, int dim)
{
  if (dim != 2 && dim != 3)
    throw std::invalid_argument("create_body_mesh: dimension " +
                                std::to_string(dim) + " (allowed: 2, 3)");
  const std::size_t per_cell = dim + 1, num_cells = cells.size() / per_cell;
  if (cell_body.size() != num_cells)
    throw std::invalid_argument("create_body_mesh: one body id per cell");
  std::vector<std::int32_t> offsets(num_cells + 1);
  for (std::size_t c = 0; c <= num_cells; ++c)
    offsets[c] = per_cell * c;
  graph::AdjacencyList<std::int64_t> adj(
      std::vector<std::int64_t>(cells.begin(), cells.end()), offsets);
  fem::CoordinateElement cmap(
      dim == 2 ? mesh::CellType::triangle : mesh::CellType::tetrahedron, 1);
  auto mesh = std::make_shared<dolfinx::mesh::Mesh>(
      mesh::create_mesh(comm, adj, cmap, x, {x.size() / dim, std::size_t(dim)},
                        mesh::GhostMode::none));

  // dolfinx reorders cells; original_cell_index maps back to the input.
  const std::vector<std::int64_t>& original =
      mesh->topology().original_cell_index;
  std::vector<int> body(original.size());
  for (std::size_t c = 0; c < original.size(); ++c)
    body[c] = cell_body[original[c]];
  const int n = count_bodies(body);
  return {mesh, std::move(body), n};
}
} // namespace softpack::bodies
