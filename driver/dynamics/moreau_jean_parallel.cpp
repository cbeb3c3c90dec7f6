// The parts of a Moreau–Jean step that differ when the bodies are spread
// over MPI ranks (docs/mpi_design.md): the detection by shares, W's rows of
// a rank's contacts from every rank's blocks, and the body terms of the
// energy accounts summed over the ranks.
#include "moreau_jean.h"
#include "moreau_jean_step.h"
#include <compliance/delassus.h>
#include <detection/detection.h>

#include <algorithm>
#include <parallel/rebalance.h>

namespace softpack::dynamics
{
namespace
{
/// A block of W on the wire (Eigen's matrices are not plain bytes): its
/// body (-1 when not needed), row, column and entries in column order
struct WireBlock
{
  std::int32_t body, a, b;
  double entries[4];
};

WireBlock to_wire(std::int32_t body, std::int32_t a, std::int32_t b,
                  const Eigen::Matrix2d& block)
{
  return {body, a, b, {block(0, 0), block(1, 0), block(0, 1), block(1, 1)}};
}

Eigen::Matrix2d from_wire(const WireBlock& w)
{
  return Eigen::Map<const Eigen::Matrix2d>(w.entries);
}

/// Each rank's blocks sent to the owners of their rows, and this rank's
/// rows received, in the body order of the serial build (each body's blocks
/// come from its one owner, in its order): W's rows then sum alike.
std::vector<DelassusBlock> route_blocks(const parallel::Communicator& comm,
                                        const std::vector<DelassusBlock>& mine,
                                        std::span<const int> row_owner)
{
  std::vector<std::vector<WireBlock>> to_rank(comm.size());
  for (const DelassusBlock& k : mine)
    to_rank[row_owner[k.a]].push_back(to_wire(k.body, k.a, k.b, k.block));
  std::vector<DelassusBlock> blocks;
  for (const WireBlock& w : comm.exchange_items(to_rank))
    blocks.push_back({w.body, w.a, w.b, from_wire(w)});
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const DelassusBlock& x, const DelassusBlock& y)
                   { return x.body < y.body; });
  return blocks;
}
} // namespace

std::vector<Contact> MoreauJean::detect(std::span<const double> x) const
{
  std::vector<Contact> contacts =
      detect_contacts(_bodies, x, _walls, _detection);
  if (!_dist.distributed())
    return contacts;
  contacts = _dist.comm().gather_items<Contact>(contacts);
  const int nb = _bodies.num_bodies();
  std::stable_sort(contacts.begin(), contacts.end(),
                   [nb](const Contact& a, const Contact& b) {
                     return contact_order_key(a, nb) < contact_order_key(b, nb);
                   });
  return contacts;
}

void MoreauJean::rebalance()
{
  if (!_dist.distributed())
    return;
  // A body's work: its DOFs (assembly, factorization, solves) and its
  // contacts as candidate (Delassus blocks, its rank's NLGS share), one
  // contact costing as much as 35 DOFs: the paper case over Phi 0.80 ->
  // 0.82 on one rank spent 0.82 us per DOF and 29 us per contact and step
  // (docs/mpi_design.md).
  constexpr double contact_weight = 35;
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
  std::vector<int> split = parallel::drifted_split(
      _dist, _bodies, _bodies.current_coordinates(), weights, links,
      _options.parallel.rebalance_tolerance);
  if (split.empty())
    return;
  // Every node vector follows the new storage; the arriving bodies'
  // entries come from their old owners (the retry's copies are empty when
  // no retry is possible; the kept tangent is assembled again right after).
  std::vector<double>* const vectors[] = {
      &_v, &_f_ext, &_f_int, &_v_contact, &_u_tangent, &_retry_u, &_retry_v};
  parallel::move_bodies(_dist, std::move(split), _bodies, vectors);
  _kbar.set_local(_bodies);
  _K = _bodies.create_matrices();
  _products_valid = false;
  // The arriving bodies' internal force, at the displacement their former
  // owner computed it at (the step's start): the same bits.
  _bodies.internal_force(_f_int);
  _rigid.zero(_f_int);
}

void MoreauJean::prepare_output()
{
  if (!_dist.distributed() || _strain_shared)
    return;
  _body_strain = _bodies.body_strain_energy();
  _dist.scatterer().share_by_body(_body_strain, 1);
  _strain_shared = true;
}

std::vector<int> MoreauJean::contact_owners() const
{
  if (!_dist.distributed())
    return {};
  // A contact belongs to its candidate node's body.
  const std::vector<int>& body_rank = _dist.index_map().body_rank();
  std::vector<int> owner(_contacts.size());
  for (std::size_t a = 0; a < _contacts.size(); ++a)
    owner[a] = body_rank[_contacts[a].candidate_body];
  return owner;
}

void MoreauJean::set_delassus(const StepContacts& sc,
                              contact::FrictionContactProblem2D& problem,
                              StepReport& report)
{
  const auto t0 = clock::now();
  std::vector<DelassusBlock> blocks = delassus_blocks(
      _bodies, sc.H, _kbar, _options.contact.delassus_drop_tolerance, &_rigid);
  const std::vector<int> owner = contact_owners();
  std::vector<char> rows;
  if (_dist.distributed())
  {
    blocks = route_blocks(_dist.comm(), blocks, owner);
    rows.resize(owner.size());
    for (std::size_t a = 0; a < owner.size(); ++a)
      rows[a] = owner[a] == _dist.comm().rank();
  }
  problem.W = assemble_delassus(sc.H.size(), blocks, sc.servo.couplings, rows);
  _domains.reset();
  _sweep_plan.reset();
  if (_dist.distributed())
    _domains.emplace(_dist.comm(), problem.W, owner, _contact_traffic);
  report.seconds.delassus += seconds_since(t0);
}

contact::FrictionContactProblem2D MoreauJean::whole_problem(
    const contact::FrictionContactProblem2D& problem) const
{
  if (!_dist.distributed())
    return problem;
  const contact::DelassusMatrix& W = problem.W;
  std::vector<WireBlock> mine;
  for (const std::vector<std::int32_t>& stage : _domains->plan().stages)
    for (const std::int32_t a : stage)
    {
      mine.push_back(to_wire(-1, a, a, W.diagonal(a)));
      const auto columns = W.row_columns(a);
      const auto blocks = W.row_blocks(a);
      for (std::size_t k = 0; k < columns.size(); ++k)
        mine.push_back(to_wire(-1, a, columns[k], blocks[k]));
    }
  contact::FrictionContactProblem2D whole = problem;
  whole.W = contact::DelassusMatrix(W.num_contacts());
  for (const WireBlock& w : _dist.comm().gather_items<WireBlock>(mine))
    whole.W.add_block(w.a, w.b, from_wire(w));
  whole.W.finalize();
  return whole;
}

void MoreauJean::share_contact_nodes(
    const std::vector<std::vector<std::int32_t>>& contact_nodes,
    std::span<double> global) const
{
  if (!_dist.distributed())
    return;
  // Only the contact nodes' entries: every rank knows which they are.
  std::vector<std::int32_t> nodes;
  for (std::size_t b = 0; b < contact_nodes.size(); ++b)
    for (const std::int32_t node : contact_nodes[b])
      nodes.push_back(_bodies.body(static_cast<int>(b)).nodes[node]);
  _dist.scatterer().share_nodes(global, nodes);
}

void MoreauJean::add_local_body_terms(const BodyStep& step,
                                      double stiffness_numerical)
{
  const double h = _h, th = _options.time.theta;
  const std::span<const int> local = _bodies.local_bodies();
  if (!_dist.distributed())
  {
    // Added in place: the serial sums keep their order of operations.
    _energy.numerical += stiffness_numerical;
    add_body_terms(_energy, h, th, step, local);
    _body_kinetic = kinetic_energy(step.v_new, step.Mv_new, local);
    return;
  }
  EnergyBalance mine;
  mine.numerical = stiffness_numerical;
  add_body_terms(mine, h, th, step, local);
  double sums[4] = {mine.damping, mine.numerical, mine.external_work,
                    kinetic_energy(step.v_new, step.Mv_new, local)};
  _dist.comm().sum(sums);
  _energy.damping += sums[0];
  _energy.numerical += sums[1];
  _energy.external_work += sums[2];
  _body_kinetic = sums[3];
}

} // namespace softpack::dynamics
