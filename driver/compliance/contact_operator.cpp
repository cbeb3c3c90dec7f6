#include "contact_operator.h"

namespace softpack::dynamics
{

template <int D>
void ContactOperator::add_contact(
    const Eigen::Matrix<double, D, D>& frame,
    const Eigen::Matrix<double, D, 1>& wall_velocity)
{
  _offsets.push_back(static_cast<std::int32_t>(_terms.size()));
  _frames.insert(_frames.end(), frame.data(), frame.data() + D * D);
  _wall_velocity.insert(_wall_velocity.end(), wall_velocity.data(),
                        wall_velocity.data() + D);
}

ContactOperator::ContactOperator(const std::vector<Contact>& contacts,
                                 const std::vector<Wall>& walls,
                                 const PeriodicCell* cell)
{
  for (const Contact& c : contacts)
  {
    _terms.push_back({c.candidate_body, c.candidate_node, 1.0});
    if (c.antagonist_body >= 0)
    {
      _terms.push_back({c.antagonist_body, c.segment[0], -(1 - c.xi)});
      _terms.push_back({c.antagonist_body, c.segment[1], -c.xi});
    }
    Eigen::Matrix2d frame;
    frame << c.n[0], c.t[0], c.n[1], c.t[1];
    Eigen::Vector2d vw = Eigen::Vector2d::Zero();
    if (c.wall >= 0)
      vw = frame.transpose() * Eigen::Vector2d(walls[c.wall].velocity[0],
                                               walls[c.wall].velocity[1]);
    else if (cell && (c.image[0] != 0 || c.image[1] != 0))
    {
      const std::array<double, 2> rate = cell->rate(c.image);
      vw = frame.transpose() * Eigen::Vector2d(rate[0], rate[1]);
    }
    add_contact<2>(frame, vw);
  }
}

ContactOperator::ContactOperator(const std::vector<Contact3D>& contacts,
                                 const std::vector<Wall3D>& walls)
    : _dim(3)
{
  for (const Contact3D& c : contacts)
  {
    _terms.push_back({c.candidate_body, c.candidate_node, 1.0});
    if (c.antagonist_body >= 0)
      for (int i = 0; i < 3; ++i)
        if (c.weights[i] != 0) // (an edge's or a vertex's zero weights)
          _terms.push_back({c.antagonist_body, c.triangle[i], -c.weights[i]});
    Eigen::Matrix3d frame;
    for (int i = 0; i < 3; ++i)
      frame.row(i) << c.n[i], c.t1[i], c.t2[i];
    Eigen::Vector3d vw = Eigen::Vector3d::Zero();
    if (c.wall >= 0)
      vw = frame.transpose() * Eigen::Vector3d(walls[c.wall].velocity.data());
    add_contact<3>(frame, vw);
  }
}

template <int D>
std::vector<double>
ContactOperator::relative_velocity_d(const bodies::BodySet& bodies,
                                     std::span<const double> v) const
{
  using Vector = Eigen::Matrix<double, D, 1>;
  std::vector<double> U(D * size());
  for (std::size_t a = 0; a < size(); ++a)
  {
    Vector va = Vector::Zero();
    for (const NodeTerm& term : terms(a))
    {
      const std::int32_t g = bodies.body(term.body).nodes[term.node];
      va += term.weight * Vector(Eigen::Map<const Vector>(v.data() + D * g));
    }
    const Eigen::Matrix<double, D, D> F = frame<D>(a);
    const Vector u = F.transpose() * va - wall_velocity<D>(a);
    for (int c = 0; c < D; ++c)
      U[D * a + c] = u[c];
  }
  return U;
}

std::vector<double>
ContactOperator::relative_velocity(const bodies::BodySet& bodies,
                                   std::span<const double> v) const
{
  return _dim == 2 ? relative_velocity_d<2>(bodies, v)
                   : relative_velocity_d<3>(bodies, v);
}

template <int D>
void ContactOperator::add_impulses_d(
    std::span<const double> R, std::vector<Eigen::VectorXd>& per_body) const
{
  using Vector = Eigen::Matrix<double, D, 1>;
  for (std::size_t a = 0; a < size(); ++a)
  {
    const Eigen::Matrix<double, D, D> F = frame<D>(a);
    const Vector impulse = F * Vector(Eigen::Map<const Vector>(&R[D * a]));
    for (const NodeTerm& term : terms(a))
      if (per_body[term.body].size() > 0)
        per_body[term.body].template segment<D>(D * term.node) +=
            term.weight * impulse;
  }
}

void ContactOperator::add_impulses(std::span<const double> R,
                                   std::vector<Eigen::VectorXd>& per_body) const
{
  if (_dim == 2)
    add_impulses_d<2>(R, per_body);
  else
    add_impulses_d<3>(R, per_body);
}

} // namespace softpack::dynamics
