#include "BodySet.h"

#include "body_assembly.h"
#include <algorithm>
#include <body.h>
#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace softpack::bodies
{
using namespace dolfinx;

namespace
{
/// Twice the signed area of triangle (a, b, c).
double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c)
{
  return (x[2 * b] - x[2 * a]) * (x[2 * c + 1] - x[2 * a + 1]) -
         (x[2 * b + 1] - x[2 * a + 1]) * (x[2 * c] - x[2 * a]);
}

/// The body's reference area, boundary segments and boundary nodes
/// (body-local numbers)
void trace_boundary(Body& body, const fem::DofMap& dofmap,
                    std::span<const std::int32_t> node_local,
                    std::span<const double> x)
{
  // An edge on the boundary belongs to one cell only; orienting each
  // cell's edges counter-clockwise orients boundary edges outward-right.
  std::unordered_map<std::int64_t, std::pair<int, std::array<std::int32_t, 2>>>
      edges;
  const std::int64_t n = body.nodes.size();
  for (std::int32_t c : body.cells)
  {
    auto d = dofmap.cell_dofs(c);
    std::array<std::int32_t, 3> v = {node_local[d[0]], node_local[d[1]],
                                     node_local[d[2]]};
    const double a2 = signed_area2(x, d[0], d[1], d[2]);
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
} // namespace

BodySet::BodySet(BodyMesh mesh, const forms::MaterialForms& material,
                 const std::map<std::string, double>& parameters,
                 double density)
    : BodySet(std::move(mesh), {BodyMaterial{&material, parameters, density}},
              {})
{
}

BodySet::BodySet(BodyMesh mesh, std::vector<BodyMaterial> materials,
                 std::vector<int> body_material)
    : _mesh(mesh.mesh), _cell_body(std::move(mesh.cell_body)),
      _materials(std::move(materials)), _body_material(std::move(body_material))
{
  if (_materials.empty())
    throw std::invalid_argument("BodySet: no material");
  for (const BodyMaterial& m : _materials)
    _constants.push_back(material_constants(m));
  _V = std::make_shared<fem::FunctionSpace>(fem::create_functionspace(
      _materials.front().law->function_space, "v", _mesh));
  _Q = std::make_shared<fem::FunctionSpace>(fem::create_functionspace(
      functionspace_form_body_current_area, "q", _mesh));
  _u = std::make_shared<fem::Function<double>>(_V);

  build_bodies();
  if (_body_material.empty())
    _body_material.assign(_bodies.size(), 0);
  if (_body_material.size() != _bodies.size())
    throw std::invalid_argument(
        "BodySet: " + std::to_string(_body_material.size()) +
        " body materials for " + std::to_string(_bodies.size()) + " bodies");
  for (int k : _body_material)
    if (k < 0 || k >= static_cast<int>(_materials.size()))
      throw std::invalid_argument("BodySet: body material " +
                                  std::to_string(k) + " out of range");
  build_forms();
  build_assembly();
  build_mass();
}

std::shared_ptr<fem::Form<double>> BodySet::make_form(
    const ConstantMap& constants, const ufcx_form& form,
    const std::vector<std::shared_ptr<const fem::FunctionSpace>>& spaces) const
{
  const std::map<std::string, std::shared_ptr<const fem::Function<double>>>
      coefficients = {{"u", _u}};
  return std::make_shared<fem::Form<double>>(fem::create_form<double>(
      form, spaces, coefficients, constants, {}, _mesh));
}

void BodySet::build_assembly()
{
  // The per-body forms lend their kernels and constants to the body
  // assembly, and go: nothing else reads them (kept, they would hold a list
  // of every cell each).
  const std::vector<std::shared_ptr<const fem::FunctionSpace>> v = {_V},
                                                               vv = {_V, _V};
  std::vector<std::shared_ptr<fem::Form<double>>> made;
  std::vector<BodyForms> forms;
  std::vector<int> body_form(_bodies.size(), 0);
  for (std::size_t f = 0; f < _forms.size(); ++f)
  {
    const int k = _forms[f].material;
    const forms::MaterialForms& law = *_materials[k].law;
    const ConstantMap& c = _constants[k];
    for (const auto& [form, rank] :
         {std::pair{law.residual, 1}, std::pair{law.tangent, 2},
          std::pair{form_body_mass, 2}, std::pair{form_body_lumped_mass, 2}})
      made.push_back(make_form(c, *form, rank == 1 ? v : vv));
    forms.push_back({made[made.size() - 4].get(), made[made.size() - 3].get(),
                     made[made.size() - 2].get(), made.back().get()});
    for (std::size_t b = 0; b < _bodies.size(); ++b)
      if (_body_material[b] == k)
        body_form[b] = static_cast<int>(f);
  }
  _assembly = std::make_unique<BodyAssembly>(forms, body_form, _u);
}

void BodySet::build_forms()
{
  auto make = [&](const ConstantMap& constants, const ufcx_form& f,
                  std::vector<std::shared_ptr<const fem::FunctionSpace>> spaces)
  { return make_form(constants, f, spaces); };
  // One material in use: its forms over all cells, exactly as with one
  // material; several: each material's forms over its own bodies' cells.
  std::vector<int> used(_body_material.begin(), _body_material.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  if (used.empty())
    used.push_back(0);
  for (int k : used)
  {
    const forms::MaterialForms& law = *_materials[k].law;
    const ConstantMap& c = _constants[k];
    MaterialForms f{k, make(c, *law.energy, {}),
                    make(c, *law.energy_density, {_Q})};
    if (used.size() > 1)
    {
      std::vector<std::int32_t> cells;
      for (std::size_t b = 0; b < _bodies.size(); ++b)
        if (_body_material[b] == k)
          cells.insert(cells.end(), _bodies[b].cells.begin(),
                       _bodies[b].cells.end());
      std::sort(cells.begin(), cells.end());
      for (auto* form : {&f.energy, &f.energy_density})
        *form = restrict_to_cells(**form, cells);
    }
    _forms.push_back(std::move(f));
  }
  _current_area = make(_constants.front(), *form_body_current_area, {_Q});
  _reference_area = make(_constants.front(), *form_body_reference_area, {_Q});
}

BodySet::BodySet(BodySet&&) noexcept = default;
BodySet::~BodySet() = default;

std::span<double> BodySet::displacement()
{
  return _u->x()->mutable_array();
}

void BodySet::build_bodies()
{
  const fem::DofMap& dofmap = *_V->dofmap();
  const std::int32_t num_nodes =
      dofmap.index_map->size_local() + dofmap.index_map->num_ghosts();
  const std::vector<double> dof_x = _V->tabulate_dof_coordinates(false);
  _reference_x.resize(2 * num_nodes);
  for (std::int32_t i = 0; i < num_nodes; ++i)
  {
    _reference_x[2 * i] = dof_x[3 * i];
    _reference_x[2 * i + 1] = dof_x[3 * i + 1];
  }

  const int num_bodies =
      _cell_body.empty()
          ? 0
          : *std::max_element(_cell_body.begin(), _cell_body.end()) + 1;
  _bodies.assign(num_bodies, Body{});
  // Body and local number of each global node (for the bodies' lists)
  std::vector<std::int32_t> node_body(num_nodes, -1), node_local(num_nodes, -1);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(_cell_body.size());
       ++c)
  {
    const int b = _cell_body[c];
    _bodies[b].cells.push_back(c);
    for (std::int32_t node : dofmap.cell_dofs(c))
    {
      if (node_body[node] != -1 && node_body[node] != b)
        throw std::runtime_error("bodies " + std::to_string(b) + " and " +
                                 std::to_string(node_body[node]) +
                                 " share a node: bodies must be disjoint");
      node_body[node] = b;
    }
  }
  for (int b = 0; b < num_bodies; ++b)
    if (_bodies[b].cells.empty())
      throw std::runtime_error("body " + std::to_string(b) + " has no cells");

  // Local numbering: increasing global node index within each body.
  for (std::int32_t node = 0; node < num_nodes; ++node)
  {
    if (node_body[node] < 0)
      continue;
    Body& body = _bodies[node_body[node]];
    node_local[node] = static_cast<std::int32_t>(body.nodes.size());
    body.nodes.push_back(node);
  }

  rank_input_order();
  for (Body& body : _bodies)
  {
    trace_boundary(body, dofmap, node_local, _reference_x);
    body.cell_nodes.reserve(body.cells.size());
    for (std::int32_t c : body.cells)
    {
      auto d = dofmap.cell_dofs(c);
      body.cell_nodes.push_back(
          {node_local[d[0]], node_local[d[1]], node_local[d[2]]});
    }
  }
}

void BodySet::rank_input_order()
{
  // A P1 cell lists its DOF blocks as its geometry nodes (both follow the
  // reference cell's vertices), which carry the input file's indices.
  const fem::DofMap& dofmap = *_V->dofmap();
  const mesh::Geometry& geometry = _mesh->geometry();
  const std::vector<std::int64_t>& input = geometry.input_global_indices();
  std::vector<std::int64_t> node_input(_reference_x.size() / 2, -1);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(_cell_body.size());
       ++c)
  {
    auto dofs = dofmap.cell_dofs(c);
    auto x = geometry.dofmap().links(c);
    for (std::size_t i = 0; i < dofs.size(); ++i)
      node_input[dofs[i]] = input[x[i]];
  }
  for (Body& body : _bodies)
  {
    std::vector<std::int32_t> order(body.nodes.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::int32_t a, std::int32_t b) {
                return node_input[body.nodes[a]] < node_input[body.nodes[b]];
              });
    body.input_rank.assign(order.size(), 0);
    for (std::size_t r = 0; r < order.size(); ++r)
      body.input_rank[order[r]] = static_cast<std::int32_t>(r);
  }
}

std::vector<double> BodySet::current_coordinates() const
{
  const std::span<const double> u = _u->x()->array();
  std::vector<double> x(_reference_x);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += u[i];
  return x;
}

void BodySet::internal_force(std::span<double> f) const
{
  if (f.size() != num_dofs())
    throw std::invalid_argument("internal_force: wrong vector size");
  std::fill(f.begin(), f.end(), 0.0);
  _assembly->residual(f, _bodies, _reference_x, _u->x()->array());
}

void BodySet::owned_internal_force(std::span<double> f) const
{
  if (f.size() != num_dofs())
    throw std::invalid_argument("internal_force: wrong vector size");
  std::fill(f.begin(), f.end(), 0.0);
  _assembly->residual(f, _bodies, _reference_x, _u->x()->array(), _owned);
}

double BodySet::strain_energy() const
{
  double e = 0;
  for (const MaterialForms& f : _forms)
    e += fem::assemble_scalar(*f.energy);
  return e;
}

std::vector<double> BodySet::assemble_cellwise(const fem::Form<double>& L) const
{
  const fem::DofMap& dofmap = *_Q->dofmap();
  std::vector<double> b(dofmap.index_map->size_local() +
                        dofmap.index_map->num_ghosts());
  fem::assemble_vector(std::span<double>(b), L);
  std::vector<double> per_cell(_cell_body.size());
  for (std::size_t c = 0; c < per_cell.size(); ++c)
    per_cell[c] = b[dofmap.cell_dofs(c)[0]];
  return per_cell;
}

std::vector<double>
BodySet::sum_per_body(const std::vector<double>& per_cell) const
{
  std::vector<double> sums(_bodies.size(), 0.0);
  for (std::size_t c = 0; c < per_cell.size(); ++c)
    sums[_cell_body[c]] += per_cell[c];
  return sums;
}

std::vector<double> BodySet::cell_strain_energy() const
{
  std::vector<double> e = assemble_cellwise(*_forms.front().energy_density);
  for (std::size_t k = 1; k < _forms.size(); ++k)
  {
    // Each material's form is zero on the other materials' cells.
    const std::vector<double> more =
        assemble_cellwise(*_forms[k].energy_density);
    for (std::size_t c = 0; c < e.size(); ++c)
      e[c] += more[c];
  }
  return e;
}

std::vector<double> BodySet::body_strain_energy() const
{
  return sum_per_body(cell_strain_energy());
}

std::vector<double> BodySet::cell_reference_area() const
{
  return assemble_cellwise(*_reference_area);
}

std::vector<double> BodySet::cell_current_area() const
{
  return assemble_cellwise(*_current_area);
}

std::vector<double> BodySet::body_current_area() const
{
  // The integral of det F over a P1 body is the signed area of its
  // deformed boundary polygon (shoelace): a pass over the boundary instead
  // of an assembly over every cell, cheap enough for every time step.
  const std::span<const double> u = _u->x()->array();
  std::vector<double> area(_bodies.size(), 0.0);
  for (std::size_t b = 0; b < _bodies.size(); ++b)
  {
    const Body& body = _bodies[b];
    auto x = [&](std::int32_t local, int c)
    {
      const std::int32_t g = body.nodes[local];
      return _reference_x[2 * g + c] + u[2 * g + c];
    };
    double twice = 0;
    for (const auto& [p, q] : body.boundary_segments)
      twice += x(p, 0) * x(q, 1) - x(q, 0) * x(p, 1);
    area[b] = 0.5 * twice;
  }
  return area;
}

} // namespace softpack::bodies
