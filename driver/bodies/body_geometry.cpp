#include "body_geometry.h"

#include <algorithm>
#include <dolfinx/fem/FunctionSpace.h>
#include <dolfinx/fem/utils.h>
#include <material_registry.h>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace softpack::bodies
{
using namespace dolfinx;

namespace
{
/// The body's reference area, boundary segments and boundary nodes
/// (body-local numbers)
void trace_boundary(Body& body, const BodyGeometry& g,
                    std::span<const std::int32_t> node_local)
{
  // An edge on the boundary belongs to one cell only; orienting each
  // cell's edges counter-clockwise orients boundary edges outward-right.
  std::unordered_map<std::int64_t, std::pair<int, std::array<std::int32_t, 2>>>
      edges;
  const std::int64_t n = body.nodes.size();
  for (std::int32_t c : body.cells)
  {
    const CellNodes& d = g.cells[c];
    std::array<std::int32_t, 3> v = {node_local[d[0]], node_local[d[1]],
                                     node_local[d[2]]};
    const double a2 = signed_area2(g.x, d[0], d[1], d[2]);
    if (a2 < 0)
      std::swap(v[1], v[2]);
    body.reference_area += 0.5 * std::abs(a2);
    for (int e = 0; e < 3; ++e)
    {
      const std::int32_t p = v[e], q = v[(e + 1) % 3];
      auto& [count, edge] = edges[std::min(p, q) * n + std::max(p, q)];
      ++count;
      edge = {p, q};
    }
  }
  for (const auto& [key, entry] : edges)
    if (entry.first == 1)
      body.boundary_segments.push_back(entry.second);
  std::sort(body.boundary_segments.begin(), body.boundary_segments.end());
  body.segment_from.assign(body.nodes.size(), -1);
  body.segment_to.assign(body.nodes.size(), -1);
  for (std::size_t k = 0; k < body.boundary_segments.size(); ++k)
  {
    const auto& s = body.boundary_segments[k];
    body.boundary_nodes.push_back(s[0]);
    body.segment_from[s[0]] = static_cast<std::int32_t>(k);
    body.segment_to[s[1]] = static_cast<std::int32_t>(k);
  }
  std::sort(body.boundary_nodes.begin(), body.boundary_nodes.end());
}

/// The body's reference volume, boundary faces and boundary nodes (3D;
/// body-local numbers)
void trace_faces(Body& body, const BodyGeometry& g,
                 std::span<const std::int32_t> node_local)
{
  // A face on the boundary belongs to one cell only; each cell's faces,
  // oriented out of the cell, are out of the body there.
  std::unordered_map<std::int64_t, std::pair<int, std::array<std::int32_t, 3>>>
      faces;
  const std::int64_t n = body.nodes.size();
  for (std::int32_t c : body.cells)
  {
    const CellNodes& d = g.cells[c];
    const double v6 = signed_volume6(g.x, d[0], d[1], d[2], d[3]);
    body.reference_area += std::abs(v6) / 6;
    std::array<std::int32_t, 4> v;
    for (int i = 0; i < 4; ++i)
      v[i] = node_local[d[i]];
    if (v6 < 0)
      std::swap(v[2], v[3]);
    // Face opposite vertex i of a positive tetrahedron, outward
    static constexpr int face[4][3] = {
        {1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (const auto& f : face)
    {
      std::array<std::int32_t, 3> tri = {v[f[0]], v[f[1]], v[f[2]]};
      std::array<std::int32_t, 3> key = tri;
      std::sort(key.begin(), key.end());
      auto& [count, oriented] = faces[(key[0] * n + key[1]) * n + key[2]];
      ++count;
      oriented = tri;
    }
  }
  std::vector<char> on_boundary(body.nodes.size(), 0);
  for (const auto& [key, entry] : faces)
    if (entry.first == 1)
    {
      body.boundary_faces.push_back(entry.second);
      for (std::int32_t k : entry.second)
        on_boundary[k] = 1;
    }
  std::sort(body.boundary_faces.begin(), body.boundary_faces.end());
  for (std::size_t k = 0; k < on_boundary.size(); ++k)
    if (on_boundary[k])
      body.boundary_nodes.push_back(static_cast<std::int32_t>(k));
}

/// Each node's position within its body in the input file's node order
void number_input_order(Body& body, std::span<const std::int64_t> node_input)
{
  std::vector<std::int32_t> order(body.nodes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::int32_t a, std::int32_t b)
            { return node_input[body.nodes[a]] < node_input[body.nodes[b]]; });
  body.input_position.assign(order.size(), 0);
  for (std::size_t r = 0; r < order.size(); ++r)
    body.input_position[order[r]] = static_cast<std::int32_t>(r);
}

/// Each cell's body, checking that no node belongs to two bodies
std::vector<std::int32_t> node_bodies(const BodyGeometry& g)
{
  std::vector<std::int32_t> node_body(g.num_nodes(), -1);
  for (std::size_t c = 0; c < g.cells.size(); ++c)
  {
    const int b = g.cell_body[c];
    for (std::int32_t node : g.cells[c])
    {
      if (node_body[node] != -1 && node_body[node] != b)
        throw std::runtime_error("bodies " + std::to_string(b) + " and " +
                                 std::to_string(node_body[node]) +
                                 " share a node: bodies must be disjoint");
      node_body[node] = b;
    }
  }
  return node_body;
}
} // namespace

double signed_volume6(std::span<const double> x, std::int32_t a, std::int32_t b,
                      std::int32_t c, std::int32_t d)
{
  double e[3][3];
  for (int k = 0; k < 3; ++k)
  {
    e[0][k] = x[3 * b + k] - x[3 * a + k];
    e[1][k] = x[3 * c + k] - x[3 * a + k];
    e[2][k] = x[3 * d + k] - x[3 * a + k];
  }
  return e[2][0] * (e[0][1] * e[1][2] - e[0][2] * e[1][1]) +
         e[2][1] * (e[0][2] * e[1][0] - e[0][0] * e[1][2]) +
         e[2][2] * (e[0][0] * e[1][1] - e[0][1] * e[1][0]);
}

double cell_measure(std::span<const double> x, const CellNodes& cell, int dim)
{
  return dim == 3
             ? std::abs(signed_volume6(x, cell[0], cell[1], cell[2], cell[3])) /
                   6
             : 0.5 * std::abs(signed_area2(x, cell[0], cell[1], cell[2]));
}

double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c)
{
  return (x[2 * b] - x[2 * a]) * (x[2 * c + 1] - x[2 * a + 1]) -
         (x[2 * b + 1] - x[2 * a + 1]) * (x[2 * c] - x[2 * a]);
}

SpaceFunction displacement_space(const std::vector<BodyMaterial>& materials,
                                 int dim)
{
  if (materials.empty())
    throw std::invalid_argument("BodySet: no material");
  return forms::in_dimension(*materials.front().law, dim).function_space;
}

int BodyGeometry::num_bodies() const
{
  return cell_body.empty()
             ? 0
             : *std::max_element(cell_body.begin(), cell_body.end()) + 1;
}

BodyGeometry body_geometry(const BodyMesh& mesh, SpaceFunction function_space)
{
  const fem::FunctionSpace V =
      fem::create_functionspace(function_space, "v", mesh.mesh);
  const fem::DofMap& dofmap = *V.dofmap();
  const int dim = mesh.mesh->geometry().dim();
  if (dofmap.bs() != dim || dofmap.cell_dofs(0).size() != std::size_t(dim + 1))
    throw std::invalid_argument(
        "body_geometry: the displacement space is not P1 vectors on the "
        "mesh's cells (triangles in 2D, tetrahedra in 3D)");
  const std::int32_t num_nodes =
      dofmap.index_map->size_local() + dofmap.index_map->num_ghosts();
  BodyGeometry g;
  g.dim = dim;
  const std::vector<double> dof_x = V.tabulate_dof_coordinates(false);
  g.x.resize(dim * num_nodes);
  for (std::int32_t i = 0; i < num_nodes; ++i)
    for (int c = 0; c < dim; ++c)
      g.x[dim * i + c] = dof_x[3 * i + c];
  // A P1 cell lists its DOF blocks as its geometry nodes (both follow the
  // reference cell's vertices), which carry the input file's indices.
  const mesh::Geometry& geometry = mesh.mesh->geometry();
  const std::vector<std::int64_t>& input = geometry.input_global_indices();
  g.cell_body = mesh.cell_body;
  g.cells.resize(g.cell_body.size());
  g.node_input.assign(num_nodes, -1);
  for (std::size_t c = 0; c < g.cells.size(); ++c)
  {
    auto dofs = dofmap.cell_dofs(static_cast<std::int32_t>(c));
    auto x = geometry.dofmap().links(static_cast<std::int32_t>(c));
    for (std::size_t i = 0; i < dofs.size(); ++i)
    {
      g.cells[c][i] = dofs[i];
      g.node_input[dofs[i]] = input[x[i]];
    }
  }
  return g;
}

BodyGeometry read_body_geometry(const std::filesystem::path& xdmf,
                                SpaceFunction function_space)
{
  const BodyMesh mesh = read_body_mesh(MPI_COMM_SELF, xdmf);
  const int dim = mesh.mesh->geometry().dim();
  if (function_space("v")->finite_element->topological_dimension != dim)
    throw std::runtime_error(
        "mesh file " + xdmf.string() + ": " +
        (dim == 3 ? "tetrahedra (3D bodies)" : "triangles (2D bodies)") +
        ", but the forms given are " + (dim == 3 ? "2D" : "3D") +
        " (3D bodies have no time loop yet: docs/bodies_3d.md)");
  return body_geometry(mesh, function_space);
}

std::vector<Body> build_bodies(const BodyGeometry& g)
{
  std::vector<Body> bodies(g.num_bodies());
  for (std::size_t c = 0; c < g.cells.size(); ++c)
    bodies[g.cell_body[c]].cells.push_back(static_cast<std::int32_t>(c));
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].cells.empty())
      throw std::runtime_error("body " + std::to_string(b) + " has no cells");

  // Local numbering: increasing global node index within each body.
  const std::vector<std::int32_t> node_body = node_bodies(g);
  std::vector<std::int32_t> node_local(g.num_nodes(), -1);
  for (std::int32_t node = 0; node < g.num_nodes(); ++node)
  {
    if (node_body[node] < 0)
      continue;
    Body& body = bodies[node_body[node]];
    node_local[node] = static_cast<std::int32_t>(body.nodes.size());
    body.nodes.push_back(node);
  }
  for (Body& body : bodies)
  {
    body.dim = g.dim;
    body.global_nodes = body.nodes;
    number_input_order(body, g.node_input);
    if (g.dim == 3)
      trace_faces(body, g, node_local);
    else
      trace_boundary(body, g, node_local);
    body.cell_nodes.reserve(body.cells.size());
    for (std::int32_t c : body.cells)
    {
      CellNodes local;
      for (int i = 0; i < g.cells[c].size(); ++i)
        local[i] = node_local[g.cells[c][i]];
      body.cell_nodes.push_back(local);
    }
  }
  return bodies;
}

} // namespace softpack::bodies
