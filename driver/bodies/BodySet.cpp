#include "BodySet.h"

#include "parallel_residual.h"
#include <algorithm>
#include <body.h>
#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <stdexcept>
#include <unordered_map>

namespace softpack::bodies
{
using namespace dolfinx;

namespace
{
using ConstantMap =
    std::map<std::string, std::shared_ptr<const fem::Constant<double>>>;

/// Every constant the material declares must be given, and nothing else
/// (driver.json's material.parameters are exactly the law's constants).
ConstantMap
make_material_constants(const forms::MaterialForms& material,
                        const std::map<std::string, double>& parameters)
{
  const std::vector<std::string> declared =
      forms::material_parameters(material);
  std::string allowed;
  for (const std::string& d : declared)
    allowed += (allowed.empty() ? "" : ", ") + d;
  auto fail = [&](const std::string& name, const std::string& what)
  {
    throw std::invalid_argument("material.parameters." + name + ": " + what +
                                " (law '" + std::string(material.name) +
                                "' has the parameters " + allowed + ")");
  };
  ConstantMap constants;
  for (const std::string& name : declared)
  {
    auto it = parameters.find(name);
    if (it == parameters.end())
      fail(name, "missing");
    constants[name] = std::make_shared<fem::Constant<double>>(it->second);
  }
  for (const auto& [name, value] : parameters)
    if (std::find(declared.begin(), declared.end(), name) == declared.end())
      fail(name, "unknown parameter");
  return constants;
}

/// Twice the signed area of triangle (a, b, c).
double signed_area2(std::span<const double> x, std::int32_t a, std::int32_t b,
                    std::int32_t c)
{
  return (x[2 * b] - x[2 * a]) * (x[2 * c + 1] - x[2 * a + 1]) -
         (x[2 * b + 1] - x[2 * a + 1]) * (x[2 * c] - x[2 * a]);
}
} // namespace

BodySet::BodySet(BodyMesh mesh, const forms::MaterialForms& material,
                 const std::map<std::string, double>& parameters,
                 double density)
    : _mesh(mesh.mesh), _cell_body(std::move(mesh.cell_body)), _density(density)
{
  if (!(density > 0))
    throw std::invalid_argument("density must be positive");
  _constants = make_material_constants(material, parameters);
  _constants["rho"] = std::make_shared<fem::Constant<double>>(density);

  _V = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(material.function_space, "v", _mesh));
  _Q = std::make_shared<fem::FunctionSpace>(fem::create_functionspace(
      functionspace_form_body_current_area, "q", _mesh));
  _u = std::make_shared<fem::Function<double>>(_V);

  using FormPtr = std::shared_ptr<fem::Form<double>>;
  const std::map<std::string, std::shared_ptr<const fem::Function<double>>>
      coefficients = {{"u", _u}};
  auto make = [&](const ufcx_form& f,
                  std::vector<std::shared_ptr<const fem::FunctionSpace>> spaces)
  {
    return std::make_shared<fem::Form<double>>(fem::create_form<double>(
        f, spaces, coefficients, _constants, {}, _mesh));
  };
  _energy = make(*material.energy, {});
  _residual = make(*material.residual, {_V});
  _tangent = make(*material.tangent, {_V, _V});
  _energy_density = make(*material.energy_density, {_Q});
  _current_area = make(*form_body_current_area, {_Q});
  _reference_area = make(*form_body_reference_area, {_Q});

  build_bodies();
  build_mass();
  _parallel_residual =
      std::make_unique<ParallelResidual>(*_residual, _u, _bodies);
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
  _node_body.assign(num_nodes, -1);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(_cell_body.size());
       ++c)
  {
    const int b = _cell_body[c];
    _bodies[b].cells.push_back(c);
    for (std::int32_t node : dofmap.cell_dofs(c))
    {
      if (_node_body[node] != -1 && _node_body[node] != b)
        throw std::runtime_error("bodies " + std::to_string(b) + " and " +
                                 std::to_string(_node_body[node]) +
                                 " share a node: bodies must be disjoint");
      _node_body[node] = b;
    }
  }
  for (int b = 0; b < num_bodies; ++b)
    if (_bodies[b].cells.empty())
      throw std::runtime_error("body " + std::to_string(b) + " has no cells");

  // Local numbering: increasing global node index within each body.
  _node_local.assign(num_nodes, -1);
  for (std::int32_t node = 0; node < num_nodes; ++node)
  {
    if (_node_body[node] < 0)
      continue;
    Body& body = _bodies[_node_body[node]];
    _node_local[node] = static_cast<std::int32_t>(body.nodes.size());
    body.nodes.push_back(node);
  }

  for (Body& body : _bodies)
  {
    // An edge on the boundary belongs to one cell only; orienting each
    // cell's edges counter-clockwise orients boundary edges outward-right.
    std::unordered_map<std::int64_t,
                       std::pair<int, std::array<std::int32_t, 2>>>
        edges;
    const std::int64_t n = body.nodes.size();
    for (std::int32_t c : body.cells)
    {
      auto d = dofmap.cell_dofs(c);
      std::array<std::int32_t, 3> v = {_node_local[d[0]], _node_local[d[1]],
                                       _node_local[d[2]]};
      const double a2 = signed_area2(_reference_x, d[0], d[1], d[2]);
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
}

std::vector<BodyMatrix> BodySet::create_matrices() const
{
  const fem::DofMap& dofmap = *_V->dofmap();
  std::vector<BodyMatrix> matrices;
  matrices.reserve(_bodies.size());
  for (const Body& body : _bodies)
  {
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(36 * body.cells.size());
    for (std::int32_t c : body.cells)
      for (std::int32_t ni : dofmap.cell_dofs(c))
        for (std::int32_t nj : dofmap.cell_dofs(c))
          for (int ci = 0; ci < 2; ++ci)
            for (int cj = 0; cj < 2; ++cj)
              pattern.emplace_back(2 * _node_local[ni] + ci,
                                   2 * _node_local[nj] + cj, 0.0);
    BodyMatrix A(body.num_dofs(), body.num_dofs());
    A.setFromTriplets(pattern.begin(), pattern.end());
    A.makeCompressed();
    matrices.push_back(std::move(A));
  }
  return matrices;
}

namespace
{
/// Assemble a bilinear form into per-body matrices holding its pattern.
void assemble_by_body(const fem::Form<double>& a,
                      const std::vector<std::int32_t>& node_body,
                      const std::vector<std::int32_t>& node_local,
                      std::vector<BodyMatrix>& matrices)
{
  for (BodyMatrix& A : matrices)
    std::fill_n(A.valuePtr(), A.nonZeros(), 0.0);
  auto add = [&](std::span<const std::int32_t> rows,
                 std::span<const std::int32_t> cols,
                 std::span<const double> values)
  {
    BodyMatrix& A = matrices[node_body[rows[0]]];
    const std::size_t ncols = 2 * cols.size();
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int ci = 0; ci < 2; ++ci)
        for (std::size_t j = 0; j < cols.size(); ++j)
          for (int cj = 0; cj < 2; ++cj)
            A.coeffRef(2 * node_local[rows[i]] + ci,
                       2 * node_local[cols[j]] + cj) +=
                values[(2 * i + ci) * ncols + 2 * j + cj];
    return 0;
  };
  fem::assemble_matrix(add, a, {});
}
} // namespace

void BodySet::tangent(std::vector<BodyMatrix>& K) const
{
  assemble_by_body(*_tangent, _node_body, _node_local, K);
}

void BodySet::build_mass()
{
  auto form = [&](const ufcx_form& f) {
    return fem::create_form<double>(f, {_V, _V}, {}, _constants, {}, _mesh);
  };
  _mass = create_matrices();
  assemble_by_body(form(*form_body_mass), _node_body, _node_local, _mass);

  std::vector<BodyMatrix> lumped = create_matrices();
  assemble_by_body(form(*form_body_lumped_mass), _node_body, _node_local,
                   lumped);
  _lumped_mass.clear();
  for (const BodyMatrix& A : lumped)
    _lumped_mass.push_back(A.diagonal());
}

void BodySet::internal_force(std::span<double> f) const
{
  if (f.size() != num_dofs())
    throw std::invalid_argument("internal_force: wrong vector size");
  std::fill(f.begin(), f.end(), 0.0);
  if (_parallel_residual->supported())
    _parallel_residual->assemble(f, _bodies);
  else
    fem::assemble_vector(f, *_residual);
}

bool BodySet::parallel_residual() const
{
  return _parallel_residual->supported();
}

double BodySet::strain_energy() const
{
  return fem::assemble_scalar(*_energy);
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
  return assemble_cellwise(*_energy_density);
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
