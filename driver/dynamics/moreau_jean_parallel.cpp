// The parts of a Moreau–Jean step that differ when the bodies are spread
// over MPI ranks (docs/mpi_design.md): the detection by shares, W from
// every rank's blocks, and the body terms of the energy accounts summed
// over the ranks.
#include "delassus.h"
#include "detection.h"
#include "moreau_jean.h"

#include <algorithm>
#include <cstdlib>

namespace softpack::dynamics
{
namespace
{
/// Doubles per block on the wire: body, a, b and the 2x2 block.
constexpr int block_size = 7;

/// Every rank's blocks, on every rank, in the body order of the serial
/// build (each body's blocks come from its one owner, in its order).
std::vector<DelassusBlock> share_blocks(const parallel::Ownership& own,
                                        const std::vector<DelassusBlock>& mine)
{
  std::vector<double> packed;
  packed.reserve(block_size * mine.size());
  for (const DelassusBlock& k : mine)
    packed.insert(packed.end(),
                  {double(k.body), double(k.a), double(k.b), k.block(0, 0),
                   k.block(1, 0), k.block(0, 1), k.block(1, 1)});
  const std::vector<double> all = own.gather(packed);
  std::vector<DelassusBlock> blocks(all.size() / block_size);
  for (std::size_t i = 0; i < blocks.size(); ++i)
  {
    const double* p = &all[block_size * i];
    blocks[i].body = static_cast<std::int32_t>(p[0]);
    blocks[i].a = static_cast<std::int32_t>(p[1]);
    blocks[i].b = static_cast<std::int32_t>(p[2]);
    blocks[i].block << p[3], p[5], p[4], p[6];
  }
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const DelassusBlock& x, const DelassusBlock& y)
                   { return x.body < y.body; });
  return blocks;
}
} // namespace

std::vector<Contact> MoreauJean::detect(std::span<const double> x) const
{
  std::vector<Contact> contacts =
      detect_contacts(_bodies, x, _walls, _detection, _own.owned());
  if (!_own.distributed())
    return contacts;
  contacts = _own.gather_items<Contact>(contacts);
  const int nb = _bodies.num_bodies();
  std::stable_sort(contacts.begin(), contacts.end(),
                   [nb](const Contact& a, const Contact& b) {
                     return contact_order_key(a, nb) < contact_order_key(b, nb);
                   });
  return contacts;
}

void MoreauJean::rebalance()
{
  if (!_own.distributed())
    return;
  // A body's work: its DOFs (assembly, factorization, solves) and its
  // contacts as candidate (Delassus blocks, its rank's NLGS share), one
  // contact costing as much as 35 DOFs: the paper case over Phi 0.80 ->
  // 0.82 on one rank spent 0.82 us per DOF and 29 us per contact and step
  // (docs/mpi_design.md). A drift of 10 % in work or cut contacts makes
  // the others wait or talk about as much as a split costs once.
  constexpr double contact_weight = 35;
  double tolerance = 0.1;
  // Test hook (tests/python/test_mpi.py): a small run rebalances at 0.
  if (const char* t = std::getenv("SOFTPACK_TEST_REBALANCE_TOLERANCE"))
    tolerance = std::atof(t);
  const int nb = _bodies.num_bodies();
  std::vector<double> weights(nb);
  for (int b = 0; b < nb; ++b)
    weights[b] = _bodies.body(b).num_dofs();
  std::vector<std::array<int, 2>> links;
  for (const Contact& c : _contacts)
  {
    weights[c.candidate_body] += contact_weight;
    if (c.antagonist_body >= 0)
      links.push_back({c.candidate_body, c.antagonist_body});
  }
  if (!_own.rebalance(_bodies, _bodies.current_coordinates(), weights, links,
                      tolerance))
    return;
  _kbar.set_owned(_bodies, _own.owned());
  _K = _bodies.create_matrices(_own.owned());
  _products_valid = false;
}

contact::DelassusMatrix
MoreauJean::delassus(const ContactOperator& H,
                     std::span<const WallCoupling> walls) const
{
  std::vector<DelassusBlock> blocks = delassus_blocks(
      _bodies, H, _kbar, _options.contact.delassus_drop_tolerance, &_rigid,
      _own.owned());
  if (_own.distributed())
    blocks = share_blocks(_own, blocks);
  return assemble_delassus(H.size(), blocks, walls);
}

std::optional<parallel::ContactDomains>
MoreauJean::contact_domains(const contact::FrictionContactProblem2D& problem)
{
  if (!_own.distributed())
    return std::nullopt;
  // A contact belongs to its candidate node's body.
  std::vector<int> owner(_contacts.size());
  for (std::size_t a = 0; a < _contacts.size(); ++a)
    owner[a] = _own.body_rank()[_contacts[a].candidate_body];
  return std::optional<parallel::ContactDomains>(std::in_place, _own.comm(),
                                                 problem.W, std::move(owner),
                                                 _contact_traffic);
}

void MoreauJean::share_contact_nodes(
    const std::vector<std::vector<std::int32_t>>& contact_nodes,
    std::span<double> global) const
{
  if (!_own.distributed())
    return;
  // Only the contact nodes' entries: every rank knows which they are.
  std::vector<std::int32_t> nodes;
  for (std::size_t b = 0; b < contact_nodes.size(); ++b)
    for (const std::int32_t node : contact_nodes[b])
      nodes.push_back(_bodies.body(static_cast<int>(b)).nodes[node]);
  _own.share_nodes(global, nodes);
}

void MoreauJean::add_owned_body_terms(const BodyStep& step)
{
  const double h = _h, th = _options.time.theta;
  if (!_own.distributed())
  {
    add_body_terms(_energy, h, th, step);
    return;
  }
  EnergyBalance mine;
  add_body_terms(mine, h, th, step, _own.owned());
  double sums[3] = {mine.damping, mine.numerical, mine.external_work};
  _own.sum(sums);
  _energy.damping += sums[0];
  _energy.numerical += sums[1];
  _energy.external_work += sums[2];
}

} // namespace softpack::dynamics
