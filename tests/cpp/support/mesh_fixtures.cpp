#include "mesh_fixtures.h"

#include <algorithm>
#include <cmath>
#include <dolfinx/fem/utils.h>
#include <dolfinx/io/XDMFFile.h>
#include <dolfinx/mesh/MeshTags.h>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace softpack::test
{

Triangulation disk(double cx, double cy, double R, int n)
{
  Triangulation t;
  auto ring_start = [](int k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  auto ring_size = [](int k) { return k == 0 ? 1 : 6 * k; };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j < ring_size(k); ++j)
    {
      const double r = R * k / n;
      const double a = 2 * std::numbers::pi * j / ring_size(k);
      t.x.push_back(cx + r * std::cos(a));
      t.x.push_back(cy + r * std::sin(a));
    }
  // Zip rings k-1 and k by increasing angle; each triangle is
  // counter-clockwise.
  for (int k = 1; k <= n; ++k)
  {
    const int m0 = ring_size(k - 1), m1 = ring_size(k);
    const int s0 = ring_start(k - 1), s1 = ring_start(k);
    int i = (k == 1) ? m0 : 0, j = 0; // the centre has no next node
    while (i < m0 || j < m1)
    {
      const double ai = (k == 1) ? 1e9 : double(i + 1) / m0;
      const double aj = double(j + 1) / m1;
      const std::int64_t inner = s0 + i % m0, outer = s1 + j % m1;
      if (aj <= ai && j < m1)
      {
        t.cells.insert(t.cells.end(), {inner, outer, s1 + (j + 1) % m1});
        ++j;
      }
      else
      {
        t.cells.insert(t.cells.end(), {inner, outer, s0 + (i + 1) % m0});
        ++i;
      }
    }
  }
  return t;
}

Triangulation rectangle(double x0, double y0, double w, double h, int nx,
                        int ny)
{
  Triangulation t;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
    {
      t.x.push_back(x0 + w * i / nx);
      t.x.push_back(y0 + h * j / ny);
    }
  auto id = [nx](int i, int j) { return std::int64_t(j) * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      t.cells.insert(t.cells.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.cells.insert(t.cells.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

bodies::BodyMesh bodies_mesh(const std::vector<Triangulation>& parts,
                             MPI_Comm comm)
{
  std::vector<double> x;
  std::vector<std::int64_t> cells;
  std::vector<int> body;
  for (std::size_t p = 0; p < parts.size(); ++p)
  {
    const std::int64_t offset = x.size() / 2;
    x.insert(x.end(), parts[p].x.begin(), parts[p].x.end());
    for (std::int64_t v : parts[p].cells)
      cells.push_back(v + offset);
    body.insert(body.end(), parts[p].cells.size() / 3, static_cast<int>(p));
  }
  return bodies::create_body_mesh(comm, x, cells, body);
}

void write_body_mesh(const bodies::BodyMesh& mesh,
                     const std::filesystem::path& xdmf)
{
  std::vector<std::int32_t> cells(mesh.cell_body.size());
  std::iota(cells.begin(), cells.end(), 0);
  dolfinx::mesh::MeshTags<std::int32_t> tags(
      mesh.mesh, mesh.mesh->topology().dim(), std::move(cells),
      std::vector<std::int32_t>(mesh.cell_body.begin(), mesh.cell_body.end()));
  tags.name = "bodies";
  dolfinx::io::XDMFFile file(mesh.mesh->comm(), xdmf, "w");
  file.write_mesh(*mesh.mesh);
  file.write_meshtags(tags, "/Xdmf/Domain/Grid[@Name='" + mesh.mesh->name +
                                "']/Geometry");
}

std::shared_ptr<dolfinx::fem::Function<double>>
dolfinx_displacement(const std::shared_ptr<dolfinx::mesh::Mesh>& mesh,
                     const forms::MaterialForms& law,
                     const bodies::BodySet& bodies)
{
  auto V = std::make_shared<dolfinx::fem::FunctionSpace>(
      dolfinx::fem::create_functionspace(law.function_space, "v", mesh));
  auto u = std::make_shared<dolfinx::fem::Function<double>>(V);
  const std::span<const double> values = bodies.displacement();
  std::span<double> x = u->x()->mutable_array();
  if (x.size() != values.size())
    throw std::logic_error("dolfinx_displacement: not the bodies' mesh");
  std::copy(values.begin(), values.end(), x.begin());
  return u;
}

} // namespace softpack::test
