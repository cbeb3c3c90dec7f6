#include "delassus.h"

namespace softpack::dynamics
{
namespace
{
/// A contact's node terms on one body: (boundary slot, weight).
struct BodyShare
{
  std::int32_t contact;
  std::vector<std::pair<int, double>> slots;
};
} // namespace

contact::DelassusMatrix build_delassus(const bodies::BodySet& bodies,
                                       const ContactOperator& H,
                                       const EffectiveStiffness& Kbar)
{
  std::vector<std::vector<BodyShare>> shares(bodies.num_bodies());
  for (std::size_t a = 0; a < H.size(); ++a)
    for (const NodeTerm& term : H.terms(a))
    {
      auto& list = shares[term.body];
      if (list.empty() || list.back().contact != static_cast<std::int32_t>(a))
        list.push_back({static_cast<std::int32_t>(a), {}});
      list.back().slots.push_back(
          {Kbar.boundary_slot(term.body, term.node), term.weight});
    }

  // The compliance columns (one solve per new boundary DOF) body by body on
  // all cores; then the blocks, in order.
  const int nb = bodies.num_bodies();
#pragma omp parallel for schedule(dynamic) if (nb >= 16)
  for (int b = 0; b < nb; ++b)
  {
    if (shares[b].empty())
      continue;
    std::vector<int> slots;
    for (const BodyShare& share : shares[b])
      for (const auto& [slot, weight] : share.slots)
        slots.push_back(slot);
    Kbar.boundary_compliance(b, slots);
  }

  contact::DelassusMatrix W(H.size());
  for (int b = 0; b < nb; ++b)
  {
    if (shares[b].empty())
      continue;
    const Eigen::MatrixXd& G = Kbar.boundary_compliance(b, {});
    for (const BodyShare& sa : shares[b])
      for (const BodyShare& sb : shares[b])
      {
        Eigen::Matrix2d block = Eigen::Matrix2d::Zero();
        for (const auto& [i, wi] : sa.slots)
          for (const auto& [j, wj] : sb.slots)
            block += wi * wj * G.block<2, 2>(2 * i, 2 * j);
        W.add_block(sa.contact, sb.contact,
                    H.frame(sa.contact).transpose() * block *
                        H.frame(sb.contact));
      }
  }
  W.finalize();
  return W;
}

} // namespace softpack::dynamics
