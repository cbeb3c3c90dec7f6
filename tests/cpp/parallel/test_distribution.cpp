// The distribution seam on 1, 2 and 3 ranks (CTest runs this executable
// alone and under mpirun -np 2 and -np 3): which rank owns which body, the
// scatterer's gathers and shares, the collectives, the moving of bodies and
// the geometry broadcast, and a step's contact problem over ranks (the
// detection's shares, W's rows by owner, the whole problem). Every check
// is exact: each entry has one owner,
// whose bits every rank must receive.
#include <algorithm>
#include <bodies/BodySet.h>
#include <bodies/body_geometry.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <compliance/contact_operator.h>
#include <compliance/delassus.h>
#include <compliance/effective_stiffness.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>
#include <numeric>
#include <parallel/contact_exchange.h>
#include <parallel/distribution.h>
#include <parallel/geometry_broadcast.h>
#include <parallel/rebalance.h>

using namespace softpack;

namespace
{
int world_size()
{
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

/// Seven disks in a row (more bodies than ranks, uneven shares)
std::vector<test::Triangulation> parts()
{
  std::vector<test::Triangulation> p;
  for (int i = 0; i < 7; ++i)
    p.push_back(test::disk(0.021 * i, 0.003 * (i % 2), 0.01, 3));
  return p;
}

bodies::BodySet make_bodies()
{
  return bodies::BodySet(test::bodies_mesh(parts(), MPI_COMM_SELF),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), 1180);
}

/// A global node vector that tells every entry apart
std::vector<double> tagged(std::size_t n, double scale = 1)
{
  std::vector<double> g(n);
  for (std::size_t i = 0; i < n; ++i)
    g[i] = scale * (1 + 0.001 * static_cast<double>(i));
  return g;
}

/// The stored entries of the local bodies' nodes set from a global
/// vector, every other entry `other`
std::vector<double> owners_only(const bodies::BodySet& bodies,
                                const std::vector<double>& global, double other)
{
  std::vector<double> stored(bodies.num_dofs(), other);
  for (const int b : bodies.local_bodies())
  {
    const bodies::Body& body = bodies.body(b);
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
        stored[2 * body.nodes[k] + c] = global[2 * body.global_nodes[k] + c];
  }
  return stored;
}
} // namespace

TEST(Distribution, EveryBodyIsLocalOnExactlyOneRank)
{
  bodies::BodySet bodies = make_bodies();
  const parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const int nb = bodies.num_bodies();
  EXPECT_EQ(dist.comm().size(), world_size());
  const std::vector<int> mine(bodies.local_bodies().begin(),
                              bodies.local_bodies().end());
  EXPECT_FALSE(mine.empty());
  EXPECT_TRUE(std::is_sorted(mine.begin(), mine.end()));
  std::vector<int> all = dist.comm().gather_items<int>(mine);
  std::sort(all.begin(), all.end());
  std::vector<int> every(nb);
  std::iota(every.begin(), every.end(), 0);
  EXPECT_EQ(all, every);
  for (int b = 0; b < nb; ++b)
    EXPECT_EQ(dist.index_map().owns(b), bodies.is_local(b)) << b;
  if (dist.distributed())
  {
    EXPECT_EQ(dist.index_map().local_bodies(), mine);
    // The bodies listed by owner: each rank's block its own bodies
    const parallel::BodyIndexMap& map = dist.index_map();
    const int first = map.first_of(map.rank());
    const std::vector<int> block(map.bodies_by_owner().begin() + first,
                                 map.bodies_by_owner().begin() + first +
                                     map.owner_body_counts()[map.rank()]);
    EXPECT_EQ(block, mine);
  }
}

TEST(Scatterer, GatherToRootGivesTheGlobalVector)
{
  bodies::BodySet bodies = make_bodies();
  const parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const std::vector<double> g = tagged(bodies.num_global_dofs());
  // The entries not stored here are garbage: only the owners' are read.
  const std::vector<double> stored = owners_only(bodies, g, -7.0);
  const std::vector<double> root =
      dist.scatterer().gather_to_root(bodies, stored);
  if (dist.comm().rank() == 0)
    EXPECT_EQ(root, g);
  else
    EXPECT_TRUE(root.empty());
}

TEST(Scatterer, ShareBoundariesGivesEveryRankTheOwnersEntries)
{
  bodies::BodySet bodies = make_bodies();
  const parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const std::vector<double> g = tagged(bodies.num_global_dofs());
  std::vector<double> v = owners_only(bodies, g, 0.0);
  dist.scatterer().share_boundaries(v);
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    for (const std::int32_t k : body.boundary_nodes)
      for (int c = 0; c < 2; ++c)
        EXPECT_EQ(v[2 * body.nodes[k] + c], g[2 * body.global_nodes[k] + c])
            << "body " << b << " node " << k;
  }
  if (dist.distributed()) // the interiors not stored read NaN
    EXPECT_TRUE(std::isnan(v[2 * bodies.unstored_node()]));
}

TEST(Scatterer, ShareByBodyAndShareNodesGiveTheOwnersValues)
{
  bodies::BodySet bodies = make_bodies();
  const parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const int nb = bodies.num_bodies();
  std::vector<double> values(2 * nb, -1.0);
  for (const int b : bodies.local_bodies())
    values[2 * b] = 10.0 * b + 1, values[2 * b + 1] = 10.0 * b + 2;
  dist.scatterer().share_by_body(values, 2);
  for (int b = 0; b < nb; ++b)
  {
    EXPECT_EQ(values[2 * b], 10.0 * b + 1);
    EXPECT_EQ(values[2 * b + 1], 10.0 * b + 2);
  }
  // The first boundary node of every body, filled by its owner only
  const std::vector<double> g = tagged(bodies.num_global_dofs(), 3);
  std::vector<double> v(bodies.num_dofs(), 0.0);
  std::vector<std::int32_t> nodes;
  for (int b = 0; b < nb; ++b)
  {
    const bodies::Body& body = bodies.body(b);
    const std::int32_t k = body.boundary_nodes.front();
    nodes.push_back(body.nodes[k]);
    if (bodies.is_local(b))
      for (int c = 0; c < 2; ++c)
        v[2 * body.nodes[k] + c] = g[2 * body.global_nodes[k] + c];
  }
  dist.scatterer().share_nodes(v, nodes);
  for (int b = 0; b < nb; ++b)
  {
    const bodies::Body& body = bodies.body(b);
    const std::int32_t k = body.boundary_nodes.front();
    for (int c = 0; c < 2; ++c)
      EXPECT_EQ(v[2 * body.nodes[k] + c], g[2 * body.global_nodes[k] + c]);
  }
}

TEST(Communicator, CollectivesAreExactAndCounted)
{
  const parallel::Communicator comm(MPI_COMM_WORLD);
  const int rank = comm.rank(), size = comm.size();
  const std::size_t calls = comm.messages();
  double x[2] = {1.0 + rank, -double(rank)};
  comm.sum(x);
  EXPECT_EQ(x[0], size + size * (size - 1) / 2.0);
  double m[1] = {0.5 * rank};
  comm.max(m);
  EXPECT_EQ(m[0], 0.5 * (size - 1));
  // A copy counts into the same traffic (the same communicator)
  const parallel::Communicator copy = comm;
  const std::vector<double> mine(rank + 1, double(rank));
  const std::vector<double> all = copy.gather(mine);
  ASSERT_EQ(all.size(), std::size_t(size * (size + 1) / 2));
  EXPECT_EQ(all.back(), size - 1.0);
  std::vector<std::vector<int>> to_rank(size);
  for (int r = 0; r < size; ++r)
    to_rank[r] = {100 * rank + r};
  const std::vector<int> got = comm.exchange_items(to_rank);
  ASSERT_EQ(got.size(), std::size_t(size));
  for (int r = 0; r < size; ++r)
    EXPECT_EQ(got[r], 100 * r + rank);
  if (comm.distributed())
  {
    // sum, max: one call each; gather, exchange: two each
    EXPECT_EQ(comm.messages() - calls, 6u);
    EXPECT_GT(comm.bytes_sent(), 0u);
  }
  else
    EXPECT_EQ(comm.messages(), calls); // serial: no MPI call at all
}

TEST(Rebalance, MovedBodiesArriveWithTheirEntriesCellsAndMasses)
{
  bodies::BodySet bodies = make_bodies();
  const bodies::BodySet whole = make_bodies();
  parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const int size = dist.comm().size(), nb = bodies.num_bodies();
  const std::vector<double> g = tagged(bodies.num_global_dofs());
  const std::vector<double> h = tagged(bodies.num_global_dofs(), -2);
  const std::vector<double> u = bodies.from_global(g);
  std::copy(u.begin(), u.end(), bodies.displacement().begin());
  std::vector<double> extra = owners_only(bodies, h, 0.0);
  if (!dist.distributed())
  {
    // One rank: never a split to move to (and no message)
    const std::vector<double> weights(nb, 1.0);
    EXPECT_TRUE(parallel::drifted_split(dist, bodies, bodies.displacement(),
                                        weights, {}, 0.0)
                    .empty());
    return;
  }
  // Every body to the next rank
  std::vector<int> split(nb, 0);
  const std::vector<int> before = dist.index_map().body_rank();
  for (int b = 0; b < nb; ++b)
    split[b] = (before[b] + 1) % size;
  std::vector<double>* vectors[] = {&extra};
  parallel::move_bodies(dist, split, bodies, vectors);
  EXPECT_EQ(dist.rebalances(), 1);
  EXPECT_EQ(dist.bodies_moved(), nb);
  const std::span<const double> stored = bodies.displacement();
  for (const int b : bodies.local_bodies())
  {
    EXPECT_EQ(split[b], dist.comm().rank());
    const bodies::Body& body = bodies.body(b);
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
      {
        const std::int32_t s = 2 * body.nodes[k] + c,
                           i = 2 * body.global_nodes[k] + c;
        ASSERT_EQ(stored[s], g[i]) << "body " << b;
        ASSERT_EQ(extra[s], h[i]) << "body " << b;
      }
    // Its cells came with it: its mass is assembled again, to the bit
    const bodies::BodyMatrix& M = bodies.consistent_mass()[b];
    ASSERT_EQ(M.nonZeros(), whole.consistent_mass()[b].nonZeros());
    EXPECT_EQ(Eigen::MatrixXd(M - whole.consistent_mass()[b]).norm(), 0.0);
  }
  // And the whole vector still gathers to the same one
  const std::vector<double> root =
      dist.scatterer().gather_to_root(bodies, bodies.displacement());
  if (dist.comm().rank() == 0)
    EXPECT_EQ(root, g);
}

TEST(GeometryBroadcast, EveryRankGetsRankZerosArrays)
{
  const forms::MaterialForms& law = forms::find_material("neo_hookean");
  const bodies::BodyGeometry reference = bodies::body_geometry(
      test::bodies_mesh(parts(), MPI_COMM_SELF), law.function_space);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  bodies::BodyGeometry geometry;
  if (rank == 0)
    geometry = reference;
  parallel::broadcast_geometry(MPI_COMM_WORLD, geometry);
  EXPECT_EQ(geometry.x, reference.x);
  EXPECT_EQ(geometry.cells, reference.cells);
  EXPECT_EQ(geometry.cell_body, reference.cell_body);
  EXPECT_EQ(geometry.node_input, reference.node_input);
}

namespace
{
/// Seven disks in a row, touching within the alert distance, on a floor
std::vector<test::Triangulation> touching()
{
  std::vector<test::Triangulation> p;
  for (int i = 0; i < 7; ++i)
    p.push_back(test::disk(0.0201 * i, 0.0, 0.01, 3));
  return p;
}

bodies::BodySet touching_bodies()
{
  return bodies::BodySet(test::bodies_mesh(touching(), MPI_COMM_SELF),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(0.15e6), 1180);
}

const std::vector<dynamics::Wall> floor_wall = {
    {"floor", {0, -0.01 - 5e-5}, {0, 1}, {0, 0}}};

/// W of the bodies' contacts at h = 72 us (the paper case's matrix)
contact::DelassusMatrix delassus(parallel::ContactExchange& exchange,
                                 const bodies::BodySet& bodies,
                                 const std::vector<dynamics::Contact>& contacts)
{
  const dynamics::ContactOperator H(contacts, floor_wall);
  dynamics::EffectiveStiffness kbar(bodies, false);
  std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
  bodies.tangent(K);
  const double h = 7.2e-5, th = 0.5;
  kbar.factorize(K, 1 + h * th * 30, h * th * 1e-5 + h * h * th * th);
  return exchange.delassus(
      contacts, dynamics::delassus_blocks(bodies, H, kbar, 0, nullptr), {});
}

void expect_same_row(const contact::DelassusMatrix& W,
                     const contact::DelassusMatrix& serial, std::size_t a)
{
  EXPECT_EQ(W.diagonal(a), serial.diagonal(a)) << "row " << a;
  const auto cols = W.row_columns(a), ref = serial.row_columns(a);
  ASSERT_EQ(std::vector<std::int32_t>(cols.begin(), cols.end()),
            std::vector<std::int32_t>(ref.begin(), ref.end()))
      << "row " << a;
  for (std::size_t k = 0; k < cols.size(); ++k)
    EXPECT_EQ(W.row_blocks(a)[k], serial.row_blocks(a)[k]) << "row " << a;
}
} // namespace

TEST(ContactExchange, DetectionAndDelassusRowsAreTheSerialOnes)
{
  dynamics::DetectionOptions options;
  options.alert_distance = 5e-4;
  // The serial build: one process, every body
  bodies::BodySet whole = touching_bodies();
  parallel::ContactExchange serial_exchange{parallel::Distribution()};
  const std::vector<double> x0(whole.reference_coordinates().begin(),
                               whole.reference_coordinates().end());
  const std::vector<dynamics::Contact> serial =
      serial_exchange.detect(whole, x0, floor_wall, options);
  const contact::DelassusMatrix W0 = delassus(serial_exchange, whole, serial);
  ASSERT_GT(serial.size(), 14u); // body pairs and the floor
  // The same on this run's ranks: every rank the serial list, each the
  // rows of its own contacts, summed as in the serial build
  bodies::BodySet bodies = touching_bodies();
  parallel::ContactExchange exchange{
      parallel::Distribution(MPI_COMM_WORLD, bodies)};
  const std::vector<dynamics::Contact> contacts = exchange.detect(
      bodies, bodies.current_coordinates(), floor_wall, options);
  ASSERT_EQ(contacts.size(), serial.size());
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    EXPECT_EQ(contacts[a].candidate_body, serial[a].candidate_body) << a;
    EXPECT_EQ(contacts[a].candidate_node, serial[a].candidate_node) << a;
    EXPECT_EQ(contacts[a].antagonist_body, serial[a].antagonist_body) << a;
    EXPECT_EQ(contacts[a].wall, serial[a].wall) << a;
    EXPECT_EQ(contacts[a].gap, serial[a].gap) << a;
    EXPECT_EQ(contacts[a].n, serial[a].n) << a;
  }
  const contact::DelassusMatrix W = delassus(exchange, bodies, contacts);
  std::size_t mine = 0;
  for (std::size_t a = 0; a < contacts.size(); ++a)
    if (bodies.is_local(contacts[a].candidate_body))
    {
      expect_same_row(W, W0, a);
      ++mine;
    }
  EXPECT_GT(mine, 0u);
  EXPECT_EQ(exchange.domain() != nullptr,
            exchange.distribution().distributed());
  // An unsolved problem is gathered whole on every rank
  contact::FrictionContactProblem2D problem;
  problem.W = W;
  problem.q.assign(2 * contacts.size(), 0.0);
  problem.friction.assign(contacts.size(), 0.3);
  const contact::FrictionContactProblem2D whole_problem =
      exchange.whole_problem(problem);
  for (std::size_t a = 0; a < contacts.size(); ++a)
    expect_same_row(whole_problem.W, W0, a);
}

TEST(Rebalance, InternalVariablesLiveWithTheOwnerMoveAndGatherToRoot)
{
  const std::map<std::string, double> p = {
      {"shear_modulus", 0.15e6}, {"lame_lambda", 0.3e6},
      {"branch_ratio_1", 1.0},   {"relaxation_time_1", 0.01},
      {"branch_ratio_2", 0.5},   {"relaxation_time_2", 0.1}};
  bodies::BodySet bodies(test::bodies_mesh(parts(), MPI_COMM_SELF),
                         forms::find_material("viscoelastic_neo_hookean"), p,
                         1180);
  const int stride = bodies.internal_stride();
  ASSERT_GT(stride, 0);
  // Every cell's values told apart, as every rank would have relaxed them
  const std::vector<double> g = tagged(bodies.internal_variables().size());
  bodies.set_internal_variables(g);
  parallel::Distribution dist(MPI_COMM_WORLD, bodies);
  const std::vector<int>& cell_body = bodies.cell_body();
  const std::span<const double> mine = bodies.internal_variables();
  for (std::size_t c = 0; c < cell_body.size(); ++c)
    for (int i = 0; i < stride; ++i)
      if (bodies.is_local(cell_body[c]))
        ASSERT_EQ(mine[c * stride + i], g[c * stride + i]);
      else // another rank's to relax
        ASSERT_TRUE(std::isnan(mine[c * stride + i])) << c;
  auto gathered = [&]
  {
    return dist.scatterer().gather_cells_to_root(
        bodies, bodies.internal_variables(), stride);
  };
  if (dist.comm().rank() == 0)
    EXPECT_EQ(gathered(), g);
  else
    EXPECT_TRUE(gathered().empty());
  if (!dist.distributed())
    return;
  // Every body to the next rank: its cells' values go with it
  const int size = dist.comm().size(), nb = bodies.num_bodies();
  std::vector<int> split(nb);
  for (int b = 0; b < nb; ++b)
    split[b] = (dist.index_map().body_rank()[b] + 1) % size;
  std::vector<double>* none[] = {nullptr};
  parallel::move_bodies(dist, split, bodies, std::span(none, 0));
  const std::span<const double> after = bodies.internal_variables();
  for (std::size_t c = 0; c < cell_body.size(); ++c)
    for (int i = 0; i < stride; ++i)
      if (bodies.is_local(cell_body[c]))
        ASSERT_EQ(after[c * stride + i], g[c * stride + i]) << c;
      else
        ASSERT_TRUE(std::isnan(after[c * stride + i])) << c;
  if (dist.comm().rank() == 0)
    EXPECT_EQ(gathered(), g);
  else
    EXPECT_TRUE(gathered().empty());
}
