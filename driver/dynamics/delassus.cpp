#include "delassus.h"

#include <algorithm>

namespace softpack::dynamics
{
namespace
{
/// A contact's terms on one body.
struct BodyShare
{
  std::int32_t contact;
  std::vector<std::pair<int, double>> slots; ///< (touched-node slot, weight)
};
} // namespace

contact::DelassusMatrix build_delassus(const bodies::BodySet& bodies,
                                       const ContactOperator& H,
                                       const EffectiveStiffness& Kbar)
{
  const int nb = bodies.num_bodies();
  // Touched nodes of each body, and each contact's share of each body.
  std::vector<std::vector<std::int32_t>> touched(nb);
  for (std::size_t a = 0; a < H.size(); ++a)
    for (const NodeTerm& term : H.terms(a))
      touched[term.body].push_back(term.node);
  for (auto& nodes : touched)
  {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  std::vector<std::vector<BodyShare>> shares(nb);
  for (std::size_t a = 0; a < H.size(); ++a)
    for (const NodeTerm& term : H.terms(a))
    {
      auto& list = shares[term.body];
      if (list.empty() || list.back().contact != static_cast<std::int32_t>(a))
        list.push_back({static_cast<std::int32_t>(a), {}});
      const auto& nodes = touched[term.body];
      const int slot = std::lower_bound(nodes.begin(), nodes.end(), term.node) -
                       nodes.begin();
      list.back().slots.push_back({slot, term.weight});
    }

  contact::DelassusMatrix W(H.size());
  for (int b = 0; b < nb; ++b)
  {
    const auto& nodes = touched[b];
    if (nodes.empty())
      continue;
    const int m = static_cast<int>(nodes.size());
    // Compliance restricted to the touched DOFs: G(:, j) = Kbar^-1 e_j.
    Eigen::MatrixXd G(2 * m, 2 * m);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(bodies.body(b).num_dofs());
    for (int j = 0; j < 2 * m; ++j)
    {
      const int dof = 2 * nodes[j / 2] + j % 2;
      e[dof] = 1;
      const Eigen::VectorXd x = Kbar.solve(b, e);
      e[dof] = 0;
      for (int i = 0; i < 2 * m; ++i)
        G(i, j) = x[2 * nodes[i / 2] + i % 2];
    }
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
