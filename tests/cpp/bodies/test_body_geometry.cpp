// The bodies' geometry as plain arrays: what a rank that never reads the
// mesh builds its BodySet from (parallel::broadcast_geometry).
#include "mesh_fixtures.h"
#include <bodies/BodySet.h>
#include <bodies/body_geometry.h>
#include <bodies/material_parameters.h>
#include <gtest/gtest.h>
#include <material_registry.h>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, rho = 1180;

bodies::BodyMaterial neo_hookean()
{
  return {&forms::find_material("neo_hookean"),
          bodies::plane_strain_parameters(mu), rho};
}

bodies::BodyMesh two_disks()
{
  return test::bodies_mesh(
      {test::disk(0, 0, 0.01, 4), test::disk(0.03, 0.005, 0.012, 5)});
}

/// Two triangles of two bodies; `shared` makes them share node 2
bodies::BodyGeometry two_triangles(bool shared)
{
  bodies::BodyGeometry g;
  g.x = {0, 0, 1, 0, 0, 1, 2, 0, 3, 0, 2, 1};
  g.cells = {{0, 1, 2}, {shared ? 2 : 3, 4, 5}};
  g.cell_body = {0, 1};
  g.node_input = {0, 1, 2, 3, 4, 5};
  return g;
}
} // namespace

TEST(BodyGeometry, ASetFromTheArraysAloneIsTheSetFromTheMesh)
{
  bodies::BodyMesh mesh = two_disks();
  // The arrays as a rank receives them: copies, with the mesh gone
  bodies::BodyGeometry received;
  {
    const bodies::BodyGeometry g = bodies::body_geometry(
        mesh, forms::find_material("neo_hookean").function_space);
    received.x = g.x;
    received.cells = g.cells;
    received.cell_body = g.cell_body;
    received.node_input = g.node_input;
  }
  bodies::BodySet from_mesh(std::move(mesh), {neo_hookean()}, {});
  bodies::BodySet from_arrays(std::move(received), {neo_hookean()}, {});

  ASSERT_EQ(from_arrays.num_bodies(), 2);
  ASSERT_EQ(from_arrays.num_dofs(), from_mesh.num_dofs());
  for (int b = 0; b < 2; ++b)
  {
    const bodies::Body &p = from_arrays.body(b), &q = from_mesh.body(b);
    EXPECT_EQ(p.nodes, q.nodes);
    EXPECT_EQ(p.cells, q.cells);
    EXPECT_EQ(p.cell_nodes, q.cell_nodes);
    EXPECT_EQ(p.boundary_segments, q.boundary_segments);
    EXPECT_EQ(p.input_position, q.input_position);
    EXPECT_EQ(p.reference_area, q.reference_area);
  }
  // The same kernels on the same cells: the same bits
  for (bodies::BodySet* s : {&from_mesh, &from_arrays})
  {
    std::span<double> u = s->displacement();
    for (std::size_t i = 0; i < u.size(); ++i)
      u[i] = 1e-4 * std::sin(0.37 * i);
  }
  std::vector<double> f(from_mesh.num_dofs()), g(from_mesh.num_dofs());
  from_mesh.internal_force(f);
  from_arrays.internal_force(g);
  EXPECT_EQ(f, g);
  EXPECT_GT(from_arrays.strain_energy(), 0);
  EXPECT_EQ(from_arrays.strain_energy(), from_mesh.strain_energy());
}

TEST(BodyGeometry, TwoBodiesSharingANodeAreRefused)
{
  EXPECT_NO_THROW(bodies::build_bodies(two_triangles(false)));
  try
  {
    bodies::build_bodies(two_triangles(true));
    FAIL() << "bodies sharing a node were accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_STREQ(e.what(),
                 "bodies 1 and 0 share a node: bodies must be disjoint");
  }
}

TEST(BodyGeometry, ABodyWithNoCellIsRefused)
{
  bodies::BodyGeometry g = two_triangles(false);
  g.cell_body = {0, 2};
  try
  {
    bodies::build_bodies(g);
    FAIL() << "a body with no cell was accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_STREQ(e.what(), "body 1 has no cells");
  }
}

TEST(BodyGeometry, TheBodiesOfTwoTrianglesAreTheirTrianglesOriented)
{
  const std::vector<bodies::Body> b =
      bodies::build_bodies(two_triangles(false));
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[1].nodes, (std::vector<std::int32_t>{3, 4, 5}));
  EXPECT_EQ(b[1].cell_nodes[0], (bodies::CellNodes{0, 1, 2}));
  EXPECT_DOUBLE_EQ(b[0].reference_area, 0.5);
  EXPECT_DOUBLE_EQ(b[1].reference_area, 0.5);
  // Counter-clockwise: the body on the left of each segment
  EXPECT_EQ(b[1].boundary_segments,
            (std::vector<std::array<std::int32_t, 2>>{{0, 1}, {1, 2}, {2, 0}}));
  EXPECT_EQ(b[1].boundary_nodes, (std::vector<std::int32_t>{0, 1, 2}));
}
