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
    const std::array<std::int32_t, 3>& d = g.cells[c];
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

double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c)
{
  return (x[2 * b] - x[2 * a]) * (x[2 * c + 1] - x[2 * a + 1]) -
         (x[2 * b + 1] - x[2 * a + 1]) * (x[2 * c] - x[2 * a]);
}

SpaceFunction displacement_space(const std::vector<BodyMaterial>& materials)
{
  if (materials.empty())
    throw std::invalid_argument("BodySet: no material");
  return materials.front().law->function_space;
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
  if (dofmap.bs() != 2 || dofmap.cell_dofs(0).size() != 3)
    throw std::invalid_argument("body_geometry: the displacement space is "
                                "not P1 vectors on triangles");
  const std::int32_t num_nodes =
      dofmap.index_map->size_local() + dofmap.index_map->num_ghosts();
  BodyGeometry g;
  const std::vector<double> dof_x = V.tabulate_dof_coordinates(false);
  g.x.resize(2 * num_nodes);
  for (std::int32_t i = 0; i < num_nodes; ++i)
  {
    g.x[2 * i] = dof_x[3 * i];
    g.x[2 * i + 1] = dof_x[3 * i + 1];
  }
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
    for (std::size_t i = 0; i < 3; ++i)
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
  return body_geometry(read_body_mesh(MPI_COMM_SELF, xdmf), function_space);
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
    body.global_nodes = body.nodes;
    number_input_order(body, g.node_input);
    trace_boundary(body, g, node_local);
    body.cell_nodes.reserve(body.cells.size());
    for (std::int32_t c : body.cells)
    {
      const std::array<std::int32_t, 3>& d = g.cells[c];
      body.cell_nodes.push_back(
          {node_local[d[0]], node_local[d[1]], node_local[d[2]]});
    }
  }
  return bodies;
}

} // namespace softpack::bodies
