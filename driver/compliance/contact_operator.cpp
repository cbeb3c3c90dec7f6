#include "contact_operator.h"

namespace softpack::dynamics
{

ContactOperator::ContactOperator(const std::vector<Contact>& contacts,
                                 const std::vector<Wall>& walls,
                                 const PeriodicCell* cell)
{
  _offsets.push_back(0);
  for (const Contact& c : contacts)
  {
    _terms.push_back({c.candidate_body, c.candidate_node, 1.0});
    if (c.antagonist_body >= 0)
    {
      _terms.push_back({c.antagonist_body, c.segment[0], -(1 - c.xi)});
      _terms.push_back({c.antagonist_body, c.segment[1], -c.xi});
    }
    _offsets.push_back(static_cast<std::int32_t>(_terms.size()));
    Eigen::Matrix2d frame;
    frame << c.n[0], c.t[0], c.n[1], c.t[1];
    _frames.push_back(frame);
    Eigen::Vector2d vw = Eigen::Vector2d::Zero();
    if (c.wall >= 0)
      vw = frame.transpose() * Eigen::Vector2d(walls[c.wall].velocity[0],
                                               walls[c.wall].velocity[1]);
    else if (cell && (c.image[0] != 0 || c.image[1] != 0))
    {
      const std::array<double, 2> rate = cell->rate(c.image);
      vw = frame.transpose() * Eigen::Vector2d(rate[0], rate[1]);
    }
    _wall_velocity.push_back(vw);
  }
}

std::vector<double>
ContactOperator::relative_velocity(const bodies::BodySet& bodies,
                                   std::span<const double> v) const
{
  std::vector<double> U(2 * size());
  for (std::size_t a = 0; a < size(); ++a)
  {
    Eigen::Vector2d va = Eigen::Vector2d::Zero();
    for (const NodeTerm& term : terms(a))
    {
      const std::int32_t g = bodies.body(term.body).nodes[term.node];
      va += term.weight * Eigen::Vector2d(v[2 * g], v[2 * g + 1]);
    }
    const Eigen::Vector2d u = _frames[a].transpose() * va - _wall_velocity[a];
    U[2 * a] = u[0];
    U[2 * a + 1] = u[1];
  }
  return U;
}

void ContactOperator::add_impulses(std::span<const double> R,
                                   std::vector<Eigen::VectorXd>& per_body) const
{
  for (std::size_t a = 0; a < size(); ++a)
  {
    const Eigen::Vector2d impulse =
        _frames[a] * Eigen::Vector2d(R[2 * a], R[2 * a + 1]);
    for (const NodeTerm& term : terms(a))
      if (per_body[term.body].size() > 0)
        per_body[term.body].segment<2>(2 * term.node) += term.weight * impulse;
  }
}

} // namespace softpack::dynamics
