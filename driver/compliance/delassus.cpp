#include "delassus.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace softpack::dynamics
{
namespace
{
/// A contact's node terms on one body: (boundary slot, weight) and the
/// local nodes.
struct BodyShare
{
  std::int32_t contact;
  std::vector<std::pair<int, double>> slots;
  std::vector<std::int32_t> nodes;
};
using BodyShares = std::vector<std::vector<BodyShare>>;

/// Each body's shares of the contacts, in contact order
BodyShares body_shares(const bodies::BodySet& bodies, const ContactOperator& H,
                       const EffectiveStiffness& Kbar)
{
  BodyShares shares(bodies.num_bodies());
  for (std::size_t a = 0; a < H.size(); ++a)
    for (const NodeTerm& term : H.terms(a))
    {
      auto& list = shares[term.body];
      if (list.empty() || list.back().contact != static_cast<std::int32_t>(a))
        list.push_back({static_cast<std::int32_t>(a), {}});
      list.back().slots.push_back(
          {Kbar.boundary_slot(term.body, term.node), term.weight});
      list.back().nodes.push_back(term.node);
    }
  return shares;
}

/// A rigid body's blocks: sum_ij w_i w_j P_i Mr^-1 P_j^T, in the contacts'
/// frames
template <int D>
void rigid_body_blocks(int b, const std::vector<BodyShare>& shares,
                       const ContactOperator& H, const RigidBodies& rigid,
                       std::vector<DelassusBlockD<D>>& W)
{
  for (const BodyShare& sa : shares)
    for (const BodyShare& sb : shares)
    {
      Eigen::Matrix<double, D, D> block = Eigen::Matrix<double, D, D>::Zero();
      for (std::size_t i = 0; i < sa.nodes.size(); ++i)
        for (std::size_t j = 0; j < sb.nodes.size(); ++j)
          block += sa.slots[i].second * sb.slots[j].second *
                   rigid.of<D>().compliance(b, sa.nodes[i], sb.nodes[j]);
      W.push_back({b, sa.contact, sb.contact,
                   H.frame<D>(sa.contact).transpose() * block *
                       H.frame<D>(sb.contact)});
    }
}

/// A deformable body's blocks from its compliance columns, those below
/// drop_tolerance of their diagonals' dropped
template <int D>
void soft_body_blocks(int b, const std::vector<BodyShare>& shares,
                      const ContactOperator& H, const EffectiveStiffness& Kbar,
                      double drop_tolerance, std::vector<DelassusBlockD<D>>& W)
{
  using Block = Eigen::Matrix<double, D, D>;
  auto body_block = [&](const BodyShare& sa, const BodyShare& sb)
  {
    Block block = Block::Zero();
    for (const auto& [i, wi] : sa.slots)
      for (const auto& [j, wj] : sb.slots)
        block += wi * wj * Kbar.template boundary_block<D>(b, i, j);
    return block;
  };
  // All the body's blocks first: a pair is kept or dropped as one, so that
  // W's pattern is symmetric, which a distributed run's plan relies on
  // (contact::plan_domain). Kbar^-1 is symmetric: each pair is computed
  // once and W_ba = W_ab^T, exactly (computed apart, the two differed by
  // rounding, at twice the cost).
  const std::size_t n = shares.size();
  std::vector<Block> blocks(n * n);
  for (std::size_t ka = 0; ka < n; ++ka)
    for (std::size_t kb = ka; kb < n; ++kb)
    {
      const BodyShare &sa = shares[ka], &sb = shares[kb];
      blocks[ka * n + kb] = H.frame<D>(sa.contact).transpose() *
                            body_block(sa, sb) * H.frame<D>(sb.contact);
      if (kb != ka)
        blocks[kb * n + ka] = blocks[ka * n + kb].transpose();
    }
  std::vector<double> diagonal_norm(n);
  for (std::size_t k = 0; k < n; ++k)
    diagonal_norm[k] = blocks[k * n + k].norm();
  for (std::size_t ka = 0; ka < n; ++ka)
    for (std::size_t kb = 0; kb < n; ++kb)
    {
      const std::int32_t a = shares[ka].contact, c = shares[kb].contact;
      const double below =
          drop_tolerance * std::sqrt(diagonal_norm[ka] * diagonal_norm[kb]);
      if (a != c && drop_tolerance > 0 && blocks[ka * n + kb].norm() < below)
        continue;
      W.push_back({b, a, c, blocks[ka * n + kb]});
    }
}
} // namespace

template <int D>
std::vector<DelassusBlockD<D>>
delassus_blocks(const bodies::BodySet& bodies, const ContactOperator& H,
                const EffectiveStiffness& Kbar, double drop_tolerance,
                const RigidBodies* rigid)
{
  if (H.dim() != D)
    throw std::logic_error("delassus_blocks: contacts of another dimension");
  auto is_rigid = [&](int b) { return rigid && rigid->rigid(b); };
  const BodyShares shares = body_shares(bodies, H, Kbar);
  // The compliance columns (one solve per new boundary DOF) body by body on
  // all cores; then the blocks, in order.
  const int nb = bodies.num_bodies();
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
  {
    if (shares[b].empty() || is_rigid(b) || !bodies.is_local(b))
      continue;
    std::vector<int> slots;
    for (const BodyShare& share : shares[b])
      for (const auto& [slot, weight] : share.slots)
        slots.push_back(slot);
    Kbar.prepare_columns(b, slots);
  }
  // Each body's blocks on all cores, then joined in body order: the same
  // list, in the same order, as one thread makes.
  std::vector<std::vector<DelassusBlockD<D>>> by_body(nb);
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
  {
    if (shares[b].empty() || !bodies.is_local(b))
      continue;
    if (is_rigid(b))
      rigid_body_blocks(b, shares[b], H, *rigid, by_body[b]);
    else
      soft_body_blocks(b, shares[b], H, Kbar, drop_tolerance, by_body[b]);
  }
  std::size_t total = 0;
  for (const std::vector<DelassusBlockD<D>>& list : by_body)
    total += list.size();
  std::vector<DelassusBlockD<D>> W;
  W.reserve(total);
  for (const std::vector<DelassusBlockD<D>>& list : by_body)
    W.insert(W.end(), list.begin(), list.end());
  return W;
}

template <int D>
contact::DelassusMatrixD<D> assemble_delassus(
    std::size_t num_contacts, std::span<const DelassusBlockD<D>> blocks,
    std::span<const WallCouplingD<D>> walls, std::span<const char> rows)
{
  auto wanted = [&](std::size_t a) { return rows.empty() || rows[a]; };
  contact::DelassusMatrixD<D> W(num_contacts);
  for (const DelassusBlockD<D>& k : blocks)
    if (wanted(k.a))
      W.add_block(k.a, k.b, k.block);
  // Each coupling as one rank-one term, its diagonal blocks added after the
  // bodies' (the sums of the dense assembly it replaces, bit for bit); a
  // rank keeps whole terms, whose sums read every rank's contacts.
  for (const WallCouplingD<D>& wall : walls)
    W.add_rank_one(wall.contacts, wall.g, wall.inverse_mass);
  W.finalize();
  return W;
}

template std::vector<DelassusBlockD<2>>
delassus_blocks<2>(const bodies::BodySet&, const ContactOperator&,
                   const EffectiveStiffness&, double, const RigidBodies*);
template std::vector<DelassusBlockD<3>>
delassus_blocks<3>(const bodies::BodySet&, const ContactOperator&,
                   const EffectiveStiffness&, double, const RigidBodies*);
template contact::DelassusMatrixD<2>
    assemble_delassus<2>(std::size_t, std::span<const DelassusBlockD<2>>,
                         std::span<const WallCouplingD<2>>,
                         std::span<const char>);
template contact::DelassusMatrixD<3>
    assemble_delassus<3>(std::size_t, std::span<const DelassusBlockD<3>>,
                         std::span<const WallCouplingD<3>>,
                         std::span<const char>);

contact::DelassusMatrix assemble_delassus(std::size_t num_contacts,
                                          std::span<const DelassusBlock> blocks,
                                          std::span<const WallCoupling> walls,
                                          std::span<const char> rows)
{
  return assemble_delassus<2>(num_contacts, blocks, walls, rows);
}

contact::DelassusMatrix
build_delassus(const bodies::BodySet& bodies, const ContactOperator& H,
               const EffectiveStiffness& Kbar, double drop_tolerance,
               std::span<const WallCoupling> walls, const RigidBodies* rigid)
{
  const std::vector<DelassusBlock> blocks =
      delassus_blocks<2>(bodies, H, Kbar, drop_tolerance, rigid);
  return assemble_delassus<2>(H.size(), blocks, walls);
}

} // namespace softpack::dynamics
