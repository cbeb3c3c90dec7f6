// Per-body blocks of a multi-body mesh: topology, boundary, areas, masses.
#include "mesh_fixtures.h"
#include <bodies/BodySet.h>
#include <bodies/body_geometry.h>
#include <bodies/material_parameters.h>
#include <body.h>
#include <cmath>
#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <numbers>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180;
constexpr int rings = 5;
struct DiskSpec
{
  double cx, cy, R;
};
const std::vector<DiskSpec> disks = {{0, 0, 0.01}, {0.05, 0.01, 0.015}};

/// The two disks; their mesh in `mesh` if given (the BodySet keeps none)
bodies::BodySet two_disks(std::shared_ptr<dolfinx::mesh::Mesh>* mesh = nullptr)
{
  std::vector<test::Triangulation> parts;
  for (const DiskSpec& d : disks)
    parts.push_back(test::disk(d.cx, d.cy, d.R, rings));
  bodies::BodyMesh m = test::bodies_mesh(parts);
  if (mesh)
    *mesh = m.mesh;
  return bodies::BodySet(std::move(m), forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
}

/// The current area of each cell, by dolfinx's assembly of the UFL form
/// int det F q dx (forms/body.py) over the bodies' mesh
std::vector<double>
dolfinx_cell_current_area(const std::shared_ptr<dolfinx::mesh::Mesh>& mesh,
                          const bodies::BodySet& bodies)
{
  auto u = test::dolfinx_displacement(mesh, forms::find_material("neo_hookean"),
                                      bodies);
  auto Q = std::make_shared<const dolfinx::fem::FunctionSpace>(
      dolfinx::fem::create_functionspace(functionspace_form_body_current_area,
                                         "q", mesh));
  const auto a = dolfinx::fem::create_form<double>(*form_body_current_area, {Q},
                                                   {{"u", u}}, {}, {}, mesh);
  std::vector<double> b(Q->dofmap()->index_map->size_local());
  dolfinx::fem::assemble_vector(std::span<double>(b), a);
  std::vector<double> per_cell(bodies.cell_body().size());
  for (std::size_t c = 0; c < per_cell.size(); ++c)
    per_cell[c] = b[Q->dofmap()->cell_dofs(c)[0]];
  return per_cell;
}

/// Area of the regular polygon inscribed in the disk (the meshed domain).
double polygon_area(double R, int sides)
{
  return 0.5 * sides * R * R * std::sin(2 * std::numbers::pi / sides);
}
} // namespace

TEST(BodySet, EachDiskIsOneBodyWithItsOwnNodes)
{
  bodies::BodySet bodies = two_disks();
  ASSERT_EQ(bodies.num_bodies(), 2);
  const int nodes_per_disk = 1 + 3 * rings * (rings + 1);
  std::size_t total = 0;
  for (int b = 0; b < 2; ++b)
  {
    EXPECT_EQ(bodies.body(b).nodes.size(), nodes_per_disk);
    EXPECT_EQ(bodies.body(b).cells.size(), 6 * rings * rings);
    total += bodies.body(b).nodes.size();
  }
  EXPECT_EQ(2 * total, bodies.num_dofs());
}

TEST(BodySet, BoundaryIsTheOuterRingOrientedOutward)
{
  bodies::BodySet bodies = two_disks();
  std::span<const double> X = bodies.reference_coordinates();
  for (int b = 0; b < 2; ++b)
  {
    const bodies::Body& body = bodies.body(b);
    const DiskSpec& d = disks[b];
    EXPECT_EQ(body.boundary_nodes.size(), 6 * rings);
    EXPECT_EQ(body.boundary_segments.size(), 6 * rings);
    for (std::int32_t local : body.boundary_nodes)
    {
      const std::int32_t g = body.nodes[local];
      EXPECT_NEAR(std::hypot(X[2 * g] - d.cx, X[2 * g + 1] - d.cy), d.R, 1e-14);
    }
    for (const auto& [a, c] : body.boundary_segments)
    {
      const std::int32_t ga = body.nodes[a], gc = body.nodes[c];
      const double tx = X[2 * gc] - X[2 * ga],
                   ty = X[2 * gc + 1] - X[2 * ga + 1];
      // outward normal = tangent rotated clockwise
      const double nx = ty, ny = -tx;
      const double mx = 0.5 * (X[2 * ga] + X[2 * gc]) - d.cx;
      const double my = 0.5 * (X[2 * ga + 1] + X[2 * gc + 1]) - d.cy;
      EXPECT_GT(nx * mx + ny * my, 0);
    }
  }
}

TEST(BodySet, AreasAreThePolygonAreasAndFollowTheDeformation)
{
  std::shared_ptr<dolfinx::mesh::Mesh> mesh;
  bodies::BodySet bodies = two_disks(&mesh);
  const std::vector<double> cell_area = bodies.cell_reference_area();
  for (int b = 0; b < 2; ++b)
  {
    EXPECT_NEAR(bodies.body(b).reference_area /
                    polygon_area(disks[b].R, 6 * rings),
                1.0, 1e-13);
    double sum = 0;
    for (std::int32_t c : bodies.body(b).cells)
    {
      EXPECT_GT(cell_area[c], 0.0);
      sum += cell_area[c];
    }
    EXPECT_NEAR(sum / bodies.body(b).reference_area, 1.0, 1e-13);
  }

  // Body 1 stretched by F = diag(1.2, 0.9): area times det F = 1.08.
  std::span<const double> X = bodies.reference_coordinates();
  std::span<double> u = bodies.displacement();
  for (std::int32_t g : bodies.body(1).nodes)
  {
    u[2 * g] = 0.2 * X[2 * g];
    u[2 * g + 1] = -0.1 * X[2 * g + 1];
  }
  const std::vector<double> area = bodies.body_current_area();
  EXPECT_NEAR(area[0] / bodies.body(0).reference_area, 1.0, 1e-13);
  EXPECT_NEAR(area[1] / bodies.body(1).reference_area, 1.08, 1e-13);
  // The boundary polygon's area is the integral of det F (the UFL form),
  // also under a non-affine deformation.
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] += 1e-4 * std::sin(1e3 * X[i] + i);
  const std::vector<double> per_cell = dolfinx_cell_current_area(mesh, bodies);
  std::vector<double> from_cells(2, 0.0);
  for (std::size_t c = 0; c < per_cell.size(); ++c)
    from_cells[bodies.cell_body()[c]] += per_cell[c];
  const std::vector<double> from_boundary = bodies.body_current_area();
  for (int b = 0; b < 2; ++b)
    EXPECT_NEAR(from_boundary[b] / from_cells[b], 1.0, 1e-13);
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] -= 1e-4 * std::sin(1e3 * X[i] + i);

  const std::vector<double> energy = bodies.body_strain_energy();
  EXPECT_EQ(energy[0], 0.0);
  EXPECT_GT(energy[1], 0.0);
  EXPECT_NEAR(energy[0] + energy[1], bodies.strain_energy(), 1e-12 * energy[1]);
}

TEST(BodySet, MassMatricesCarryTheBodyMass)
{
  bodies::BodySet bodies = two_disks();
  for (int b = 0; b < 2; ++b)
  {
    const double m = rho * bodies.body(b).reference_area;
    const bodies::BodyMatrix& M = bodies.consistent_mass()[b];
    // A rigid translation along x: 1^T M 1_x = total mass
    Eigen::VectorXd ex = Eigen::VectorXd::Zero(M.rows());
    for (int i = 0; i < M.rows(); i += 2)
      ex[i] = 1;
    EXPECT_NEAR(ex.dot(bodies::symmetric_product(M, ex)) / m, 1.0, 1e-13);
    EXPECT_NEAR(bodies.lumped_mass()[b].sum() / (2 * m), 1.0, 1e-13);
    EXPECT_GT(bodies.lumped_mass()[b].minCoeff(), 0.0);
    // only the lower triangle of the symmetric mass is stored (BodyMatrix)
    const Eigen::MatrixXd dense(M);
    EXPECT_EQ(
        Eigen::MatrixXd(dense.triangularView<Eigen::StrictlyUpper>()).norm(),
        0.0);
    EXPECT_GT(
        Eigen::MatrixXd(dense.triangularView<Eigen::StrictlyLower>()).norm(),
        0.0);
  }
}

TEST(BodySet, ARankKeepsTheMassesOfItsOwnBodies)
{
  bodies::BodySet bodies = two_disks();
  const std::vector<bodies::BodyMatrix> all = bodies.consistent_mass();
  const std::vector<Eigen::VectorXd> lumped = bodies.lumped_mass();
  const bodies::Body whole = bodies.body(1);
  const std::vector<std::int32_t> lists = bodies.cell_lists(1);
  bodies.set_local({0});
  // Body 1's cells are its owner's now (parallel::move_bodies brings them)
  EXPECT_TRUE(bodies.body(1).cells.empty());
  EXPECT_TRUE(bodies.body(1).cell_nodes.empty());
  EXPECT_TRUE(bodies.body(1).input_position.empty());
  EXPECT_EQ(bodies.body(1).boundary_segments, whole.boundary_segments);
  EXPECT_THROW(bodies.set_local({1}), std::logic_error);
  EXPECT_THROW(bodies.set_local({1, 0}), std::invalid_argument);
  EXPECT_THROW(bodies.set_local({2}), std::invalid_argument);
  EXPECT_THROW(bodies.cell_reference_area(), std::logic_error);
  EXPECT_EQ(bodies.lumped_mass()[1].size(), 0);
  EXPECT_EQ(bodies.consistent_mass()[1].nonZeros(), 0);
  // ... and its storage is released (an empty sparse matrix can keep it).
  EXPECT_EQ(bodies.consistent_mass()[1].data().allocatedSize(), 0);
  EXPECT_EQ(bodies.consistent_mass()[1].rows(), all[1].rows());
  EXPECT_EQ(Eigen::MatrixXd(bodies.consistent_mass()[0] - all[0]).norm(), 0.0);
  // Body 1 comes to this rank (a rebalanced run) with its cells, body 0
  // leaves: body 1's mass is assembled again, over its own cells, to the
  // last bit.
  EXPECT_EQ(bodies.take_cell_lists(1, lists), lists.size());
  EXPECT_EQ(bodies.body(1).cells, whole.cells);
  EXPECT_EQ(bodies.body(1).cell_nodes, whole.cell_nodes);
  EXPECT_EQ(bodies.body(1).input_position, whole.input_position);
  bodies.set_local({1});
  EXPECT_TRUE(bodies.body(0).cells.empty());
  EXPECT_EQ(bodies.consistent_mass()[0].nonZeros(), 0);
  EXPECT_EQ(bodies.consistent_mass()[0].data().allocatedSize(), 0);
  const bodies::BodyMatrix& M = bodies.consistent_mass()[1];
  ASSERT_EQ(M.nonZeros(), all[1].nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(M - all[1]).norm(), 0.0);
  // The lumped masses follow the consistent ones
  EXPECT_EQ(bodies.lumped_mass()[0].size(), 0);
  ASSERT_EQ(bodies.lumped_mass()[1].size(), lumped[1].size());
  EXPECT_EQ((bodies.lumped_mass()[1] - lumped[1]).norm(), 0.0);
  EXPECT_GT(lumped[1].minCoeff(), 0.0);
  EXPECT_EQ(bodies.kept_masses(), (std::vector<char>{0, 1}));
  EXPECT_EQ(std::vector<int>(bodies.local_bodies().begin(),
                             bodies.local_bodies().end()),
            std::vector<int>{1});
  EXPECT_FALSE(bodies.is_local(0));
}

TEST(BodySet, ARankOfADistributedRunAssemblesTheMassesItKeepsOnly)
{
  // Built without masses (a distributed run's ranks), then given its
  // bodies: their masses are those of a set built with every mass, to
  // the bit, and no other body's is assembled.
  const bodies::BodySet all = two_disks();
  std::vector<test::Triangulation> parts;
  for (const DiskSpec& d : disks)
    parts.push_back(test::disk(d.cx, d.cy, d.R, rings));
  const forms::MaterialForms& law = forms::find_material("neo_hookean");
  bodies::BodySet bodies(
      bodies::body_geometry(test::bodies_mesh(parts), law.function_space),
      {{&law, bodies::plane_strain_parameters(mu), rho}}, {}, false);
  for (int b = 0; b < 2; ++b)
  {
    EXPECT_EQ(bodies.consistent_mass()[b].nonZeros(), 0);
    EXPECT_EQ(bodies.consistent_mass()[b].rows(), all.body(b).num_dofs());
    EXPECT_EQ(bodies.lumped_mass()[b].size(), 0);
  }
  bodies.set_local({1});
  EXPECT_EQ(bodies.consistent_mass()[0].nonZeros(), 0);
  const bodies::BodyMatrix& M = bodies.consistent_mass()[1];
  ASSERT_EQ(M.nonZeros(), all.consistent_mass()[1].nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(M - all.consistent_mass()[1]).norm(), 0.0);
  ASSERT_EQ(bodies.lumped_mass()[1].size(), all.lumped_mass()[1].size());
  EXPECT_EQ((bodies.lumped_mass()[1] - all.lumped_mass()[1]).norm(), 0.0);
}

TEST(BodySet, ARankStoresItsOwnBodiesAndEveryBoundary)
{
  bodies::BodySet bodies = two_disks();
  const std::size_t n = bodies.num_global_dofs();
  ASSERT_EQ(bodies.num_dofs(), n);
  EXPECT_EQ(bodies.unstored_node(), -1);
  // A displacement that tells every global entry apart
  std::vector<double> global(n);
  for (std::size_t i = 0; i < n; ++i)
    global[i] = 1e-4 * std::sin(0.37 * i);
  std::copy(global.begin(), global.end(), bodies.displacement().begin());
  const std::vector<double> X(bodies.reference_coordinates().begin(),
                              bodies.reference_coordinates().end());
  const std::vector<double> strain = bodies.body_strain_energy();
  const bodies::Body& kept = bodies.body(0);
  const bodies::Body& other = bodies.body(1);
  const std::size_t stored = kept.nodes.size() + other.boundary_nodes.size();

  bodies.keep_storage(std::vector<char>{1, 0});
  // Body 0 whole, body 1's boundary, and one entry for body 1's interior
  ASSERT_EQ(bodies.num_dofs(), 2 * (stored + 1));
  const std::int32_t unstored = bodies.unstored_node();
  EXPECT_EQ(unstored, static_cast<std::int32_t>(stored));
  const std::span<const double> u = bodies.displacement();
  const std::span<const double> Xs = bodies.reference_coordinates();
  for (const bodies::Body* body : {&kept, &other})
    for (std::size_t k = 0; k < body->nodes.size(); ++k)
    {
      const std::int32_t s = body->nodes[k], g = body->global_nodes[k];
      const bool boundary = body->segment_from[k] >= 0;
      if (body == &other && !boundary)
      {
        EXPECT_EQ(s, unstored);
        continue;
      }
      for (int c = 0; c < 2; ++c)
      {
        EXPECT_EQ(u[2 * s + c], global[2 * g + c]);
        EXPECT_EQ(Xs[2 * s + c], X[2 * g + c]);
      }
    }
  EXPECT_TRUE(std::isnan(u[2 * unstored]) && std::isnan(Xs[2 * unstored]));
  // The kept body's energy is its own, to the bit; a global vector goes in
  // and out of the storage unchanged where stored, NaN elsewhere
  bodies.set_local({0});
  EXPECT_EQ(bodies.body_strain_energy()[0], strain[0]);
  EXPECT_EQ(bodies.body_strain_energy()[1], 0.0);
  // Only body 0's stored nodes are local
  for (std::size_t k = 0; k < kept.nodes.size(); ++k)
    EXPECT_TRUE(bodies.is_local_node(kept.nodes[k]));
  for (std::size_t k = 0; k < other.nodes.size(); ++k)
    EXPECT_FALSE(bodies.is_local_node(other.nodes[k]));
  const std::vector<double> back = bodies.to_global(bodies.from_global(global));
  ASSERT_EQ(back.size(), n);
  for (std::size_t k = 0; k < kept.global_nodes.size(); ++k)
    EXPECT_EQ(back[2 * kept.global_nodes[k]], global[2 * kept.global_nodes[k]]);
  int interior = 0;
  for (std::size_t k = 0; k < other.global_nodes.size(); ++k)
  {
    const double x = back[2 * other.global_nodes[k]];
    if (other.segment_from[k] >= 0)
      EXPECT_EQ(x, global[2 * other.global_nodes[k]]);
    else
      interior += std::isnan(x);
  }
  EXPECT_EQ(interior,
            static_cast<int>(other.nodes.size() - other.boundary_nodes.size()));
  EXPECT_GT(interior, 0);

  // The bodies change owners: what stays stored keeps its value, what is
  // new is NaN until the old owner's entries arrive (parallel::move_bodies)
  std::vector<double> v(u.begin(), u.end());
  bodies.keep_storage(std::vector<char>{0, 1});
  bodies.remap(v);
  ASSERT_EQ(v.size(), bodies.num_dofs());
  for (std::size_t k = 0; k < other.nodes.size(); ++k)
  {
    const std::int32_t s = other.nodes[k], g = other.global_nodes[k];
    const bool boundary = other.segment_from[k] >= 0;
    EXPECT_EQ(std::isnan(v[2 * s]), !boundary);
    if (boundary)
      EXPECT_EQ(v[2 * s], global[2 * g]);
  }
  for (std::size_t k = 0; k < kept.nodes.size(); ++k)
    EXPECT_EQ(kept.nodes[k] == bodies.unstored_node(),
              kept.segment_from[k] < 0);
}
