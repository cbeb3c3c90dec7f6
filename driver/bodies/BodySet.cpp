#include "BodySet.h"

#include "body_assembly.h"
#include <algorithm>
#include <body.h>
#include <body_tetrahedron.h>
#include <dolfinx/fem/utils.h>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace softpack::bodies
{
using namespace dolfinx;

BodySet::BodySet(BodyMesh mesh, const forms::MaterialForms& material,
                 const std::map<std::string, double>& parameters,
                 double density)
    : BodySet(std::move(mesh), {BodyMaterial{&material, parameters, density}},
              {})
{
}

BodySet::BodySet(BodyMesh mesh, std::vector<BodyMaterial> materials,
                 std::vector<int> body_material)
    : BodySet(body_geometry(mesh, displacement_space(
                                      materials, mesh.mesh->geometry().dim())),
              materials, std::move(body_material))
{
}

BodySet::BodySet(BodyGeometry geometry, std::vector<BodyMaterial> materials,
                 std::vector<int> body_material, bool masses)
    : _materials(std::move(materials)), _body_material(std::move(body_material))
{
  if (_materials.empty())
    throw std::invalid_argument("BodySet: no material");
  _dim = geometry.dim;
  // Each law's forms of the mesh's dimension (the same law in 2D)
  for (BodyMaterial& m : _materials)
    if (m.law && m.law->dimension != _dim)
      try
      {
        m.law = &forms::in_dimension(*m.law, _dim);
      }
      catch (const std::invalid_argument& e)
      {
        throw std::invalid_argument(m.name + ".law: " + e.what());
      }
  _bodies = build_bodies(geometry);
  _cell_body = std::move(geometry.cell_body);
  _reference_x = std::move(geometry.x);
  _num_global_nodes = _reference_x.size() / _dim;
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
  _u.assign(_reference_x.size(), 0.0);
  _local.resize(_bodies.size());
  std::iota(_local.begin(), _local.end(), 0);
  _local_flag.assign(_bodies.size(), 1);
  mark_local_nodes();
  init_internal();
  build_assembly();
  build_mass(masses);
}

void BodySet::build_assembly()
{
  // The forms of each material in use lend their kernels and constants to
  // the body assembly, and go with the space: nothing else reads them. A
  // kernel reads one cell's coordinates and displacement, which the
  // assembly passes: one cell's mesh (a triangle or a tetrahedron) carries
  // the forms.
  const double triangle[] = {0, 0, 1, 0, 0, 1};
  const double tetrahedron[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::int64_t cell[] = {0, 1, 2, 3};
  const int body[] = {0};
  const std::span<const double> x =
      _dim == 3 ? std::span<const double>(tetrahedron) : triangle;
  const auto V =
      std::make_shared<const fem::FunctionSpace>(fem::create_functionspace(
          displacement_space(_materials, _dim), "v",
          create_body_mesh(MPI_COMM_SELF, x,
                           std::span(cell, std::size_t(_dim + 1)), body, _dim)
              .mesh));
  const auto u = std::make_shared<const fem::Function<double>>(V);
  const std::vector<std::shared_ptr<const fem::FunctionSpace>> none,
      v = {V}, vv = {V, V};
  std::vector<int> used(_body_material.begin(), _body_material.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<std::shared_ptr<fem::Form<double>>> made;
  std::vector<BodyForms> forms;
  std::vector<int> body_form(_bodies.size(), 0);
  for (std::size_t f = 0; f < used.size(); ++f)
  {
    const int k = used[f];
    const forms::MaterialForms& law = *_materials[k].law;
    const ConstantMap constants = material_constants(_materials[k]);
    auto make = [&](const ufcx_form* form, const auto& spaces)
    {
      made.push_back(
          std::make_shared<fem::Form<double>>(fem::create_form<double>(
              *form, spaces, {{"u", u}}, constants, {}, V->mesh())));
      return made.back().get();
    };
    BodyForms bf{
        nullptr, nullptr, nullptr,
        make(_dim == 3 ? form_body_tetrahedron_mass : form_body_mass, vv),
        make(_dim == 3 ? form_body_tetrahedron_lumped_mass
                       : form_body_lumped_mass,
             vv)};
    // A law with internal variables: its own kernels (its forms read a
    // coefficient the one-triangle mesh has no space for)
    if (law.internal_update)
      bf.internal = internal_forms(law, _materials[k].parameters);
    else
    {
      if (law.nodal_volumetric)
        bf.nodal_lambda = _materials[k].parameters.at(law.nodal_volumetric);
      bf.energy = make(law.energy, none);
      bf.residual = make(law.residual, v);
      bf.tangent = make(law.tangent, vv);
    }
    forms.push_back(std::move(bf));
    for (std::size_t b = 0; b < _bodies.size(); ++b)
      if (_body_material[b] == k)
        body_form[b] = static_cast<int>(f);
  }
  _assembly = std::make_unique<BodyAssembly>(forms, body_form, u);
  _assembly->set_internal(_internal, _internal_stride);
}

BodySet::BodySet(BodySet&&) noexcept = default;
BodySet::~BodySet() = default;

std::vector<double> BodySet::current_coordinates() const
{
  std::vector<double> x(_reference_x);
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += _u[i];
  return x;
}

void BodySet::internal_force(std::span<double> f) const
{
  if (f.size() != num_dofs())
    throw std::invalid_argument("internal_force: wrong vector size");
  std::fill(f.begin(), f.end(), 0.0);
  _assembly->residual(f, _bodies, _reference_x, _u, _local_flag);
}

double BodySet::strain_energy() const
{
  const std::vector<double> per_body = body_strain_energy();
  return std::accumulate(per_body.begin(), per_body.end(), 0.0);
}

std::vector<double> BodySet::cell_strain_energy() const
{
  std::vector<double> e(_cell_body.size(), 0.0);
  _assembly->cell_energy(e, _bodies, _reference_x, _u, _local_flag);
  return e;
}

std::vector<double> BodySet::body_strain_energy() const
{
  const std::vector<double> per_cell = cell_strain_energy();
  std::vector<double> sums(_bodies.size(), 0.0);
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    for (std::int32_t c : _bodies[b].cells)
      sums[b] += per_cell[c];
  return sums;
}

std::vector<CellNodes> BodySet::cell_global_nodes() const
{
  require_every_cell("cell_global_nodes");
  std::vector<CellNodes> nodes(_cell_body.size());
  for (const Body& body : _bodies)
    for (std::size_t k = 0; k < body.cells.size(); ++k)
      for (int i = 0; i < body.cell_nodes[k].size(); ++i)
        nodes[body.cells[k]][i] = body.global_nodes[body.cell_nodes[k][i]];
  return nodes;
}

std::vector<double> BodySet::cell_reference_area() const
{
  require_every_cell("cell_reference_area");
  std::vector<double> area(_cell_body.size());
  for (const Body& body : _bodies)
    for (std::size_t k = 0; k < body.cells.size(); ++k)
    {
      CellNodes stored = body.cell_nodes[k];
      for (std::int32_t& node : stored)
        node = body.nodes[node];
      area[body.cells[k]] = cell_measure(_reference_x, stored, _dim);
    }
  return area;
}

void BodySet::keep_storage(std::span<const char> kept)
{
  if (kept.size() != _bodies.size())
    throw std::invalid_argument("keep_storage: one flag per body");
  // Where each global node is stored now (-1: not)
  std::vector<std::int32_t> old_index(_num_global_nodes, -1);
  for (std::size_t s = 0; s < _reference_x.size() / _dim; ++s)
    if (_stored_global.empty())
      old_index[s] = static_cast<std::int32_t>(s);
    else if (static_cast<std::int32_t>(s) != _unstored)
      old_index[_stored_global[s]] = static_cast<std::int32_t>(s);
  // Every share reads every boundary and every rigid body (the same
  // indices everywhere); a kept body's interior is its own.
  std::vector<char> shared(_num_global_nodes, 0);
  std::vector<std::int32_t> interior;
  for (std::size_t b = 0; b < _bodies.size(); ++b)
  {
    const Body& body = _bodies[b];
    for (std::int32_t k : body.boundary_nodes)
      shared[body.global_nodes[k]] = 1;
    if (rigid(static_cast<int>(b)))
      for (std::int32_t g : body.global_nodes)
        shared[g] = 1;
  }
  for (std::size_t b = 0; b < _bodies.size(); ++b)
    if (kept[b])
      for (std::int32_t g : _bodies[b].global_nodes)
        if (!shared[g])
          interior.push_back(g);
  std::sort(interior.begin(), interior.end());
  std::vector<std::int32_t> stored;
  for (std::size_t g = 0; g < _num_global_nodes; ++g)
    if (shared[g])
      stored.push_back(static_cast<std::int32_t>(g));
  stored.insert(stored.end(), interior.begin(), interior.end());
  const auto unstored = static_cast<std::int32_t>(stored.size());
  std::vector<std::int32_t> new_index(_num_global_nodes, unstored);
  for (std::size_t s = 0; s < stored.size(); ++s)
    new_index[stored[s]] = static_cast<std::int32_t>(s);
  for (Body& body : _bodies)
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      body.nodes[k] = new_index[body.global_nodes[k]];
  _previous.assign(stored.size() + 1, -1);
  for (std::size_t s = 0; s < stored.size(); ++s)
    _previous[s] = old_index[stored[s]];
  _stored_global = std::move(stored);
  _stored_global.push_back(-1); // the unstored nodes' entry
  _unstored = unstored;
  remap(_u);
  remap(_reference_x);
  mark_local_nodes();
}

void BodySet::remap(std::vector<double>& v) const
{
  constexpr double none = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> out(_dim * _previous.size(), none);
  for (std::size_t s = 0; s < _previous.size(); ++s)
    if (_previous[s] >= 0)
      for (int c = 0; c < _dim; ++c)
        out[_dim * s + c] = v[_dim * _previous[s] + c];
  v = std::move(out);
}

std::vector<double> BodySet::from_global(std::span<const double> global) const
{
  if (global.size() != num_global_dofs())
    throw std::invalid_argument(
        "a global node vector of " + std::to_string(global.size()) +
        " entries, " + std::to_string(num_global_dofs()) + " expected");
  if (_stored_global.empty())
    return {global.begin(), global.end()};
  std::vector<double> out(num_dofs(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t s = 0; s < _stored_global.size(); ++s)
    if (_stored_global[s] >= 0)
      for (int c = 0; c < _dim; ++c)
        out[_dim * s + c] = global[_dim * _stored_global[s] + c];
  return out;
}

std::vector<double> BodySet::to_global(std::span<const double> stored) const
{
  if (_stored_global.empty())
    return {stored.begin(), stored.end()};
  std::vector<double> out(num_global_dofs(),
                          std::numeric_limits<double>::quiet_NaN());
  for (std::size_t s = 0; s < _stored_global.size(); ++s)
    if (_stored_global[s] >= 0)
      for (int c = 0; c < _dim; ++c)
        out[_dim * _stored_global[s] + c] = stored[_dim * s + c];
  return out;
}

std::vector<double> BodySet::body_current_area() const
{
  if (_dim == 3)
    return body_current_volume();
  // The integral of det F over a P1 body is the signed area of its
  // deformed boundary polygon (shoelace): a pass over the boundary instead
  // of an assembly over every cell, cheap enough for every time step.
  const std::span<const double> u = _u;
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

std::vector<double> BodySet::body_current_volume() const
{
  // The integral of det F over a P1 body is its deformed volume, by the
  // divergence theorem (1/3) sum over its boundary faces of x . n da =
  // (1/6) sum of x_a . (x_b x x_c), x taken from one of the body's nodes
  // (no cancellation of the far positions).
  std::vector<double> volume(_bodies.size(), 0.0);
  for (std::size_t b = 0; b < _bodies.size(); ++b)
  {
    const Body& body = _bodies[b];
    if (body.boundary_faces.empty())
      continue;
    const std::int32_t o = body.nodes[body.boundary_faces[0][0]];
    auto x = [&](std::int32_t local, int c)
    {
      const std::int32_t g = body.nodes[local];
      return _reference_x[3 * g + c] + _u[3 * g + c] -
             (_reference_x[3 * o + c] + _u[3 * o + c]);
    };
    double six = 0;
    for (const auto& [p, q, r] : body.boundary_faces)
      six += x(p, 0) * (x(q, 1) * x(r, 2) - x(q, 2) * x(r, 1)) +
             x(p, 1) * (x(q, 2) * x(r, 0) - x(q, 0) * x(r, 2)) +
             x(p, 2) * (x(q, 0) * x(r, 1) - x(q, 1) * x(r, 0));
    volume[b] = six / 6;
  }
  return volume;
}

} // namespace softpack::bodies
