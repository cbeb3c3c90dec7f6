#include "contact_exchange.h"

#include <algorithm>

namespace softpack::parallel
{
namespace
{
/// A block of W on the wire (Eigen's matrices are not plain bytes): its
/// body (-1 when not needed), row, column and D x D entries in column order
template <int D> struct WireBlockD
{
  std::int32_t body, a, b;
  double entries[D * D];
};
using WireBlock = WireBlockD<2>;

template <int D>
WireBlockD<D> to_wire(std::int32_t body, std::int32_t a, std::int32_t b,
                      const Eigen::Matrix<double, D, D>& block)
{
  WireBlockD<D> w{body, a, b, {}};
  std::copy_n(block.data(), D * D, w.entries);
  return w;
}

template <int D> Eigen::Matrix<double, D, D> from_wire(const WireBlockD<D>& w)
{
  return Eigen::Map<const Eigen::Matrix<double, D, D>>(w.entries);
}

/// The blocks received, in the body order of the serial build (each body's
/// blocks come from its one owner, in its order): W's rows then sum alike.
template <int D>
std::vector<dynamics::DelassusBlockD<D>>
in_body_order(const std::vector<WireBlockD<D>>& received)
{
  std::vector<dynamics::DelassusBlockD<D>> blocks;
  for (const WireBlockD<D>& w : received)
    blocks.push_back({w.body, w.a, w.b, from_wire(w)});
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const dynamics::DelassusBlockD<D>& x,
                      const dynamics::DelassusBlockD<D>& y)
                   { return x.body < y.body; });
  return blocks;
}

/// Each rank's blocks sent to the owners of their rows, and this rank's
/// rows received, in the body order of the serial build
std::vector<dynamics::DelassusBlock>
route_blocks(const Communicator& comm,
             const std::vector<dynamics::DelassusBlock>& mine,
             std::span<const int> row_owner)
{
  std::vector<std::vector<WireBlock>> to_rank(comm.size());
  for (const dynamics::DelassusBlock& k : mine)
    to_rank[row_owner[k.a]].push_back(to_wire<2>(k.body, k.a, k.b, k.block));
  return in_body_order(comm.exchange_items(to_rank));
}
} // namespace

ContactExchange::ContactExchange(Distribution distribution)
    : _dist(std::move(distribution))
{
}

std::vector<dynamics::Contact>
ContactExchange::detect(const bodies::BodySet& bodies,
                        std::span<const double> x,
                        const std::vector<dynamics::Wall>& walls,
                        const dynamics::DetectionOptions& options,
                        const dynamics::PeriodicCell* cell) const
{
  return in_serial_order(
      dynamics::detect_contacts(bodies, x, walls, options, cell),
      bodies.num_bodies());
}

std::vector<dynamics::Contact3D>
ContactExchange::detect(const bodies::BodySet& bodies,
                        std::span<const dynamics::BoundarySurface> surfaces,
                        std::span<const double> x,
                        const std::vector<dynamics::PlaneWall>& walls,
                        const dynamics::DetectionOptions& options) const
{
  return in_serial_order(
      dynamics::detect_contacts_3d(bodies, surfaces, x, walls, options),
      bodies.num_bodies());
}

template <typename C>
std::vector<C> ContactExchange::in_serial_order(std::vector<C> share,
                                                int num_bodies) const
{
  if (!_dist.distributed())
    return share;
  std::vector<C> contacts = _dist.comm().gather_items<C>(share);
  std::stable_sort(contacts.begin(), contacts.end(),
                   [num_bodies](const C& a, const C& b)
                   {
                     return dynamics::contact_order_key(a, num_bodies) <
                            dynamics::contact_order_key(b, num_bodies);
                   });
  return contacts;
}

contact::DelassusMatrix
ContactExchange::delassus(const std::vector<dynamics::Contact>& contacts,
                          std::vector<dynamics::DelassusBlock> blocks,
                          std::span<const dynamics::WallCoupling> couplings)
{
  _domains.reset();
  if (!_dist.distributed())
    return dynamics::assemble_delassus(contacts.size(), blocks, couplings);
  // A contact belongs to its candidate node's body.
  const std::vector<int>& body_rank = _dist.index_map().body_rank();
  const int rank = _dist.comm().rank();
  std::vector<int> owner(contacts.size());
  std::vector<char> rows(contacts.size());
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    owner[a] = body_rank[contacts[a].candidate_body];
    rows[a] = owner[a] == rank;
  }
  blocks = route_blocks(_dist.comm(), blocks, owner);
  contact::DelassusMatrix W =
      dynamics::assemble_delassus(contacts.size(), blocks, couplings, rows);
  _domains.emplace(_dist.comm(), W, owner, _traffic);
  return W;
}

contact::DelassusMatrixD<3>
ContactExchange::delassus(std::size_t num_contacts,
                          std::vector<dynamics::DelassusBlockD<3>> blocks,
                          std::span<const dynamics::WallCouplingD<3>> couplings)
{
  _domains.reset();
  if (_dist.distributed())
  {
    std::vector<WireBlockD<3>> mine;
    for (const dynamics::DelassusBlockD<3>& k : blocks)
      mine.push_back(to_wire<3>(k.body, k.a, k.b, k.block));
    blocks = in_body_order(_dist.comm().gather_items<WireBlockD<3>>(mine));
  }
  return dynamics::assemble_delassus<3>(num_contacts, blocks, couplings);
}

contact::FrictionContactProblem2D ContactExchange::whole_problem(
    const contact::FrictionContactProblem2D& problem) const
{
  if (!_dist.distributed())
    return problem;
  const contact::DelassusMatrix& W = problem.W;
  std::vector<WireBlock> mine;
  for (const std::vector<std::int32_t>& stage : _domains->plan().stages)
    for (const std::int32_t a : stage)
    {
      mine.push_back(to_wire<2>(-1, a, a, W.diagonal(a)));
      const auto columns = W.row_columns(a);
      const auto blocks = W.row_blocks(a);
      for (std::size_t k = 0; k < columns.size(); ++k)
        mine.push_back(to_wire<2>(-1, a, columns[k], blocks[k]));
    }
  contact::FrictionContactProblem2D whole = problem;
  whole.W = contact::DelassusMatrix(W.num_contacts());
  for (const WireBlock& w : _dist.comm().gather_items<WireBlock>(mine))
    whole.W.add_block(w.a, w.b, from_wire<2>(w));
  // Every rank holds the rank-one terms whole; the diagonal came with the
  // blocks.
  for (const contact::DelassusMatrix::RankOne& term : W.rank_one_terms())
    whole.W.add_rank_one(term.contacts, term.g, term.inverse_mass, false);
  whole.W.finalize();
  return whole;
}

void ContactExchange::share_contact_nodes(
    const bodies::BodySet& bodies,
    const std::vector<std::vector<std::int32_t>>& contact_nodes,
    std::span<double> global) const
{
  if (!_dist.distributed())
    return;
  // Only the contact nodes' entries: every rank knows which they are.
  std::vector<std::int32_t> nodes;
  for (std::size_t b = 0; b < contact_nodes.size(); ++b)
    for (const std::int32_t node : contact_nodes[b])
      nodes.push_back(bodies.body(static_cast<int>(b)).nodes[node]);
  _dist.scatterer().share_nodes(global, nodes);
}

} // namespace softpack::parallel
